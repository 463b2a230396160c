#!/usr/bin/env bash
# Every any-hit kernel (--gpu-trace) and ray order (--ray-order) of rtmini-bvh-bench traces the
# same rays to the same answers: the verification hash of each run equals the default's.
# Usage: same_hash.sh BENCH MESH
set -euo pipefail
bench=$1 mesh=$2
fail=0
for quality in sah lbvh; do
  ref=""
  for kernel in default wide stored short8 short16 default_lb stored_lb compact_lb wide_lb \
    shared8 shared16 wide_shared compact compact_shared16 speculative speculative_shared16 \
    speculative_compact; do
    orders=ray  # the coherent order through one kernel of each kind (it only renumbers threads)
    case $kernel in default | wide | short8 | shared16 | compact | speculative) orders="ray coherent" ;; esac
    for order in $orders; do
      line=$("$bench" "$mesh" --workload ao --quality $quality --samples-per-face 2 --rays 8 \
        --repeats 1 --threads 2 --gpu-trace $kernel --ray-order $order | grep '^FOM')
      hash=${line##* }
      echo "$quality $kernel $order: $hash"
      ref=${ref:-$hash}
      [ "$hash" = "$ref" ] || { echo "  differs from default ($ref)"; fail=1; }
    done
  done
done
# The shadow workload (any hit, camera rays' hits toward a light) through one variant too.
for kernel in default short8 shared16 compact speculative; do
  line=$("$bench" "$mesh" --workload shadow --width 48 --height 48 --repeats 1 --threads 2 \
    --gpu-trace $kernel | grep '^FOM')
  echo "shadow $kernel: ${line##* }"
  [ $kernel = default ] && ref=${line##* }
  [ "${line##* }" = "$ref" ] || { echo "  differs from default ($ref)"; fail=1; }
done
exit $fail
