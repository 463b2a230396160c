# Device call 2 of 2 (warm machine after dev_mid.sh): every any-hit kernel variant, then ncu.
source .carry/dev_env.sh
t0=$(date +%s)
[ -x build-cuda/bench/rtmini-bvh-bench ] || { echo "no build-cuda: the machine was not warm"; exit 1; }
mkdir -p $OUT/anyhit
OUT=$OUT/anyhit timeout ${ANYLIM:-560} bash results/gpu/anyhit_device.sh build-cuda ${PHASE:-all} > $OUT/anyhit.txt 2>&1; echo "anyhit rc=$? $(( $(date +%s)-t0 )) s"; tail -45 $OUT/anyhit.txt
find $OUT -name '*.log' -o -name '*.txt' | xargs sed -i "s|$(pwd)|.|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
