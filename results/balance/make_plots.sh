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
