# Mid-session call 1 (issue 21): gpu7's dynamic-fetch kernels beside the default on the trial.
source .carry/dev_env.sh
kokkos_cuda
{ echo "trial $(cat .carry/commit.txt)"; } > $OUT/trial_commit.txt
OUT=$OUT bash results/gpu/fetch_device.sh measure
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
