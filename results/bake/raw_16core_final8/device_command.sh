# Final call 2 (issue 19): strong scaling in one call, main's bake (build-main) and the trial's
# (build), each through run_distributed.sh scaling; order main, trial, then trial again if time.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "trial $(cat .carry/commit.txt), main $(cat .carry/main_commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/provenance.txt
ls -la build/miniapps/bake/bake build-main/miniapps/bake/bake || exit 3
BAKE=$R/build-main/miniapps/bake/bake timeout 200 bash results/bake/run_distributed.sh $OUT/main scaling > $OUT/main.txt 2>&1; echo "main rc=$? $(( $(date +%s)-t0 )) s"
timeout 200 bash results/bake/run_distributed.sh $OUT/trial scaling > $OUT/trial.txt 2>&1; echo "trial rc=$? $(( $(date +%s)-t0 )) s"
[ $(( $(date +%s)-t0 )) -lt 330 ] && { timeout 200 bash results/bake/run_distributed.sh $OUT/trial2 scaling > $OUT/trial2.txt 2>&1; echo "trial2 rc=$? $(( $(date +%s)-t0 )) s"; }
for f in main trial trial2; do [ -f $OUT/$f.txt ] && { echo "== $f"; grep -A9 'Strong scaling in one run' $OUT/$f.txt | tail -7; }; done
rm -f $OUT/*/*.bs $OUT/*/*.bsb
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.md' | xargs sed -i "s|$(pwd)|.|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
echo "total $(( $(date +%s)-t0 )) s"
