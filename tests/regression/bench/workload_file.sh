#!/usr/bin/env bash
# regression.bench.workload_file: rtmini-bvh-bench --write-workload writes the rays a peer
# traces and the bench's answers; check_workload.py recomputes a sample of them by brute force,
# for an any-hit (ao) and a closest-hit (primary) workload, and must reject a file with one
# sampled answer flipped.
# Usage: workload_file.sh BENCH MESH WORKDIR
set -euo pipefail
bench=$1 mesh=$2 dir=$3
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
mkdir -p "$dir"
/usr/bin/python3 -c "import numpy" 2>/dev/null ||
  { echo "skipped: /usr/bin/python3 has no numpy for the brute-force check"; exit 77; }
"$bench" "$mesh" --workload ao --samples-per-face 1 --rays 4 --repeats 1 --threads 2 \
  --write-workload "$dir/ao.rtmw" | grep '^workload written'
"$bench" "$mesh" --workload primary --width 48 --height 48 --repeats 1 --threads 2 \
  --write-workload "$dir/primary.rtmw" | grep '^workload written'
/usr/bin/python3 "$here/check_workload.py" "$dir/ao.rtmw" 400
/usr/bin/python3 "$here/check_workload.py" "$dir/primary.rtmw" 400
# Tampered: every answer of the any-hit file flipped (0 <-> 1); the check must fail.
/usr/bin/python3 - "$dir/ao.rtmw" "$dir/flipped.rtmw" <<'PY'
import sys
import numpy as np
data = bytearray(open(sys.argv[1], "rb").read())
nt, nr = (int(x) for x in np.frombuffer(bytes(data[16:32]), np.uint64))
off = 32 + nt * 36 + nr * 32
answers = np.frombuffer(bytes(data[off:]), np.int32)
data[off:] = (1 - answers).astype(np.int32).tobytes()
open(sys.argv[2], "wb").write(bytes(data))
PY
if /usr/bin/python3 "$here/check_workload.py" "$dir/flipped.rtmw" 50 >/dev/null; then
  echo "FAIL: a file with flipped answers passed the check" >&2
  exit 1
fi
echo "workload files check out; a flipped file is rejected"
