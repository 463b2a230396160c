#!/usr/bin/env bash
# Regenerates the plots of results/balance/README.md from raw/ (Debian's python3).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
export PYTHONPATH=$here/../../analysis
cd "$here"
py=/usr/bin/python3
for np in 04 16; do
  $py -m rtmini_analysis.rank_completion raw/np${np}_{static,metric,chunks,bargain,queue,steal}.h5 \
    -o "rank_completion_np$np.png"
done
$py -m rtmini_analysis.rank_completion raw_local/np04_{static,metric,chunks,bargain,queue,steal}.h5 \
  -o rank_completion_np04_devvm.png \
  --title "sketchtrace two_spheres 640x480 32 spp, 4 ranks on the 2-core development VM (oversubscribed)"
for b in queue steal bargain; do
  $py -m rtmini_analysis.scaling raw/np01_static.json raw/np0[248]_$b.json raw/np16_$b.json \
    -o "strong_scaling_$b.png" --title "sketchtrace two_spheres 800x600 32 spp, --balance $b (np1: static)"
done
# Communication-thread study (raw_thread/, after shaft culling).
$py -m rtmini_analysis.rank_completion raw_thread/np16_{bargain,bargain_thread,steal,steal_thread,queue}_rep2.h5 \
  --labels "bargain,bargain+thread,steal,steal+thread,queue" -o rank_completion_np16_thread.png \
  --title "sketchtrace two_spheres 800x600 32 spp, 16 ranks: communication thread (+thread) vs between-dispatch progress"
for b in queue steal_thread; do
  $py -m rtmini_analysis.scaling raw_thread/np01_static.json raw_thread/np0[248]_$b.json raw_thread/np16_${b}_rep2.json \
    -o "strong_scaling_${b}_h.png" --title "two_spheres 800x600 32 spp, --balance ${b/_thread/ + comm thread} (np1: static), after shaft culling"
done
# Guided dispatch sizes (raw_guided/, the current code).
$py -m rtmini_analysis.rank_completion raw_guided/np16_{bargain,queue,steal}_rep1.h5 raw_guided/np16_steal_nothread.h5 \
  --labels "bargain,queue,steal,steal (--comm-thread off)" -o rank_completion_np16_guided.png \
  --title "sketchtrace two_spheres 800x600 32 spp, 16 ranks: guided dispatch sizes, communication thread"
for b in queue steal bargain; do
  $py -m rtmini_analysis.scaling raw_guided/np01_static.json raw_guided/np0[248]_$b.json raw_guided/np16_${b}_rep1.json \
    -o "strong_scaling_${b}_guided.png" --title "two_spheres 800x600 32 spp, --balance $b (np1: static), current code"
done
