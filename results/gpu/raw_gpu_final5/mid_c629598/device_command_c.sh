# Mid-session device call C (warm, after dev_mid5_b.sh): sketchtrace main / trial / min-blocks 3 / 4
# (alternated, 3 runs each, ncu), then the AO whole bake main against the trial, 3 runs each.
source .carry/dev_env.sh
t0=$(date +%s)
builds="main=/tmp/s_main/b trial=build-cuda"
for mb in 3 4; do [ -x build-mb$mb/miniapps/sketchtrace/sketchtrace ] && builds="$builds mb$mb=build-mb$mb"; done
mkdir -p $OUT/sketch
OUT=$OUT/sketch timeout ${SKLIM:-330} bash results/gpu/sketchtrace_device.sh $builds > $OUT/sketch.txt 2>&1; echo "sketch rc=$? $(( $(date +%s)-t0 )) s"; grep -v "^ " $OUT/sketch.txt | tail -40
for rep in 1 2 3; do for b in main:/tmp/s_main/b trial:build-cuda; do
  timeout 60 ${b#*:}/miniapps/bake/bake ao inputs/ao/dragon_x4.toml -s 1250000 --fit cg -o /tmp/d.glb > $OUT/ao_${b%%:*}_rep$rep.log 2>&1
  echo "ao ${b%%:*} rep$rep rc=$? $(grep -E 'Whole bake|eceiver|verification' $OUT/ao_${b%%:*}_rep$rep.log | tr -s ' ' | tr '\n' '|')"; done; done
echo "total $(( $(date +%s)-t0 )) s"
rm -f $OUT/sketch/*.png $OUT/sketch/*.ppm
find $OUT -name '*.log' -o -name '*.txt' | xargs sed -i "s|$(pwd)|.|g; s|OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
