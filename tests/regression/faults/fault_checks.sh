#!/usr/bin/env bash
# Collective failure checks (issue 17): a failure seen by some ranks only must end
# the whole job within seconds, every rank with the same exit code, and rank 0
# must print exactly one "app...: file...: reason" line. Before the collective
# outcome these runs hung until killed.
#   one_rank APP NP      the input missing, then malformed, on the last rank only
#                        and on rank 0 only (MPMD launch: the other ranks get a good file);
#                        with HDF5 a truncated --restart checkpoint on rank 0 only
#   sketch_restart NP    sketchtrace --restart with a checkpoint of other parameters
#   sketch_reference NP  sketchtrace --reference naming a file that does not exist
#   outputs APP          every writer of APP into a missing directory, a read-only and a
#                        full filesystem (small tmpfs mounts; skipped with a reason where
#                        mounting is not allowed) and onto a fifo: exit 3, one line, no
#                        final file, no temporary left, the fifo untouched; bake's MPI-IO
#                        map with both Open MPI I/O components; sketchtrace's cost map,
#                        bake ao's .bin/.ply/.obj/.glb and bake render's images too. Stale
#                        temporaries of dead runs are removed, those of live processes kept.
#   memory APP NP        --max-memory 1MiB: exit 3 and the one "needs ~X GiB on rank r, Y GiB
#                        available" line (APP: bake, sketchtrace, bake-ao, bake-render)
#   estimate APP         the up-front memory estimate in the summary is within -25 %/+50 % of
#                        the measured peak resident set (every program, a bundled scene)
#   restart_inputs APP   one byte of a mesh (and bake's material library) changed between the
#                        checkpointed run and the restart: exit 2 naming the file; unchanged:
#                        the uninterrupted run's hash
#   places APP           --checkpoint / -o into a missing directory and a read-only one: exit 3
#                        and one line before anything is computed; -o and --summary naming one
#                        file: exit 2, the same way
#   signal APP           SIGINT during start-up: a clean stop (exit 4, a checkpoint written)
#   corrupt APP          APP's checkpoint (and sketchtrace's cost map) with one bit flipped
#                        in each dataset, truncated, and with single bytes changed across
#                        the file: restart gives exit 2 and one line, or (a harmless byte)
#                        exit 0 and the uninterrupted run's hash; never a crash. The fuzzers'
#                        HDF5 reproducers (tests/data/bad/h5_*.h5): exit 2, one stderr line.
# Environment: SKETCH, BAKE, BENCH, GEN (binaries), INPUTS, BAD (bad bake inputs), SKETCH_BAD,
# MPIEXEC, NPFLAG, HDF5 (ON when built with HDF5).
set -euo pipefail
mode=$1
work=$2
shift 2
rm -rf "$work"
mkdir -p "$work"
cd "$work"
limit=25  # seconds a failing run may take; a hang is killed here and reported
# These checks count the app's lines on the ranks' shared stderr. Oversubscribed ranks each print
# Kokkos' multi-line oversubscription warning in pieces, and a piece can land inside another
# rank's error line (faults.one_rank.bake.np4 failed ~1 run in 12 that way). The warning is
# Kokkos', not the app's, and expected here, so it is switched off for every launch below.
export KOKKOS_DISABLE_WARNINGS=1  # the spelling Kokkos 3.4 and 4 both read (4 aborts on "ON")

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

have_h5py() { "$PY" -c "import h5py" 2>/dev/null; }  # false on a host without it (the CUDA one)

# expect_one_line APP EXPECT_CODE PATTERN CMD...: runs CMD, which must exit EXPECT_CODE
# within $limit seconds and leave exactly one line of APP's on stderr, matching PATTERN.
expect_one_line() {
  local app=$1 want=$2 pattern=$3
  shift 3
  local rc=0 start end
  start=$(date +%s)
  timeout -k 5 "$limit" "$@" >out.txt 2>err.txt || rc=$?
  end=$(date +%s)
  [[ $rc != 124 && $rc != 137 ]] || fail "hung: no exit within $limit s: $*"
  [[ $rc == "$want" ]] || { cat err.txt >&2; fail "exit $rc, expected $want: $*"; }
  # Ranks share stderr: another process's partial line (e.g. Open MPI's own notices) can
  # precede the app's line without a newline; split it off.
  sed -i -E "s/(.)($app( \\(rank [0-9]+\\))?: )/\\1\\n\\2/g" err.txt
  local lines
  lines=$(grep -c "^$app" err.txt || true)
  [[ $lines == 1 ]] || { cat err.txt >&2; fail "$lines lines of $app on stderr, expected 1: $*"; }
  grep "^$app" err.txt | grep -Eq -- "$pattern" ||
    { cat err.txt >&2; fail "the line does not match '$pattern': $*"; }
  echo "ok ($((end - start)) s): $(grep "^$app" err.txt)"
}

sketch_args=(--width 80 --height 60 --spp 1 --shadow-samples 2)

mounts=()
cleanup_mounts() {
  local m
  for m in "${mounts[@]}"; do umount "$m" 2>/dev/null || true; done
}
trap cleanup_mounts EXIT
# try_mount DIR OPTIONS: a small tmpfs at DIR (false when mounting is not allowed here).
try_mount() {
  mkdir -p "$1"
  if mount -t tmpfs -o "$2" tmpfs "$1" 2>/dev/null; then
    mounts+=("$1")
    return 0
  fi
  return 1
}

# output_case APP WHERE TARGET CMD...: CMD writes TARGET (inside WHERE) and must fail
# with exit 3 and one line, leaving no file at TARGET (a fifo stays a fifo) and no
# temporary in WHERE.
output_case() {
  local app=$1 where=$2 target=$3
  shift 3
  local was_fifo=0
  [[ -p $target ]] && was_fifo=1
  expect_one_line "$app" 3 "$(basename "$target")" "$@"
  if ((was_fifo)); then
    [[ -p $target ]] || fail "the fifo $target was replaced"
  else
    [[ ! -e $target ]] || fail "$target exists after a failed write"
  fi
  local left
  for left in "$where"/*.tmp.*; do
    if [[ -e $left ]]; then fail "a temporary was left in $where: $left"; fi
  done
}
bake_args=(--viewpoints 10)

case $mode in
  one_rank)
    app=$1
    np=$2
    if [[ $app == sketchtrace ]]; then
      bin=$SKETCH good=$INPUTS/two_spheres/two_spheres.toml malformed=$SKETCH_BAD/unknown_key.toml
      args=("${sketch_args[@]}" -o out.png)
    else
      bin=$BAKE good=$INPUTS/cube/cube.bs malformed=$BAD/bs_nan.bs
      args=("${bake_args[@]}" -o out.bs)
    fi
    for bad in "$work/missing_input" "$malformed"; do
      name=$(basename "$bad")
      # the last rank only
      expect_one_line "$app" 2 "\\(rank $((np - 1))\\): .*$name" \
        "$MPIEXEC" "$NPFLAG" $((np - 1)) --oversubscribe "$bin" "$good" "${args[@]}" : \
        "$NPFLAG" 1 --oversubscribe "$bin" "$bad" "${args[@]}"
      # rank 0 only
      expect_one_line "$app" 2 "\\(rank 0\\): .*$name" \
        "$MPIEXEC" "$NPFLAG" 1 --oversubscribe "$bin" "$bad" "${args[@]}" : \
        "$NPFLAG" $((np - 1)) --oversubscribe "$bin" "$good" "${args[@]}"
      [[ ! -e out.png && ! -e out.bs ]] || fail "a failed run left its output"
    done
    # Every rank failing the same way names no rank.
    expect_one_line "$app" 2 "^$app: .*$(basename "$malformed")" \
      "$MPIEXEC" "$NPFLAG" "$np" --oversubscribe "$bin" "$malformed" "${args[@]}"
    if [[ $HDF5 == ON ]]; then
      # A checkpoint truncated on rank 0 only (the rank that reads it; the others name a
      # good one).
      if [[ $app == sketchtrace ]]; then
        ck_args=("${args[@]}" --chunk-pixels 500)
        stop=(--stop-after-chunks 2)
      else
        ck_args=("${args[@]}" --iterations 3)
        stop=(--stop-after-iteration 1)
      fi
      rc=0
      "$bin" "$good" "${ck_args[@]}" --checkpoint ck.h5 "${stop[@]}" >/dev/null 2>&1 || rc=$?
      [[ $rc == 4 ]] || fail "the stopped run gave exit $rc"
      head -c "$(($(stat -c %s ck.h5) / 2))" ck.h5 >cut.h5
      expect_one_line "$app" 2 "\\(rank 0\\): .*cut.h5" \
        "$MPIEXEC" "$NPFLAG" 1 --oversubscribe "$bin" "$good" "${ck_args[@]}" --restart cut.h5 : \
        "$NPFLAG" $((np - 1)) --oversubscribe "$bin" "$good" "${ck_args[@]}" --restart ck.h5
      rm -f out.png out.bs
    fi
    ;;
  sketch_restart)
    np=$1
    set -- "$INPUTS/two_spheres/two_spheres.toml" --width 80 --height 60 --shadow-samples 2 --chunk-pixels 500
    rc=0
    "$SKETCH" "$@" --spp 1 --checkpoint ck.h5 --stop-after-chunks 2 >stop.txt 2>&1 || rc=$?
    [[ $rc == 4 && -f ck.h5 ]] || fail "the stopped run gave exit $rc and no checkpoint"
    expect_one_line sketchtrace 2 "ck.h5: checkpoint was written with different parameters" \
      "$MPIEXEC" "$NPFLAG" "$np" --oversubscribe "$SKETCH" "$@" --spp 2 --restart ck.h5
    ;;
  sketch_reference)
    np=$1
    expect_one_line sketchtrace 2 "nonexistent.exr" \
      "$MPIEXEC" "$NPFLAG" "$np" --oversubscribe "$SKETCH" "$INPUTS/two_spheres/two_spheres.toml" \
      "${sketch_args[@]}" --reference "$work/nonexistent.exr"
    ;;
  outputs)
    app=$1
    can_mount=1
    if try_mount "$work/ro" ro,size=64k && try_mount "$work/full" size=64k; then
      # Fill the filesystem to the last block.
      dd if=/dev/zero of="$work/full/filler" bs=4k >/dev/null 2>&1 || true
    else
      can_mount=0
      echo "SKIP read-only and full filesystem cases: mounting a tmpfs is not allowed here"
    fi
    mkdir -p "$work/fifo"
    places=("$work/missing_dir")
    ((can_mount)) && places+=("$work/ro" "$work/full")
    if [[ $app == sketchtrace ]]; then
      run=("$SKETCH" "$INPUTS/two_spheres/two_spheres.toml" "${sketch_args[@]}")
      writers=("-o x.png" "-o x.exr" "-o x.ppm" "--summary x.json" "--timings x.h5"
               "--checkpoint x.h5 --stop-after-chunks 2 --chunk-pixels 500")
    else
      run=("$BAKE" "$INPUTS/cube/cube.bs" "${bake_args[@]}")
      writers=("-o x.bsb" "--summary x.json" "--timings x.h5" "--checkpoint x.h5")
    fi
    # every_place "FLAG NAME [REST]" CMD...: CMD FLAG <place>/NAME REST into every place and
    # onto a fifo.
    every_place() {
      local flag name rest dir
      read -r flag name rest <<<"$1"
      shift
      # shellcheck disable=SC2086
      for dir in "${places[@]}"; do
        output_case "$app" "$dir" "$dir/$name" "$@" $flag "$dir/$name" $rest
      done
      [[ -p $work/fifo/$name ]] || mkfifo "$work/fifo/$name"
      # shellcheck disable=SC2086
      output_case "$app" "$work/fifo" "$work/fifo/$name" "$@" $flag "$work/fifo/$name" $rest
    }
    for w in "${writers[@]}"; do
      every_place "$w" "${run[@]}"
    done
    if [[ $app == sketchtrace ]]; then
      every_place "--cost-map cm.h5 --balance metric" "${run[@]}"
    else
      # bake ao's four formats and bake render's three image formats.
      for ext in bin ply obj glb; do
        every_place "-o ao.$ext" "$BAKE" ao "$INPUTS/cube/cube.bs" -r 4
      done
      "$BAKE" "$INPUTS/cube/cube.bs" "${bake_args[@]}" -o "$work/map.bs" >/dev/null 2>&1 ||
        fail "the map for bake render was not written"
      for ext in png ppm exr; do
        every_place "-o render.$ext" "$BAKE" render "$work/map.bs" --width 16 --height 12
      done
    fi
    if [[ $app == bake ]]; then
      # The text map is written collectively through MPI-IO: both components, 2 ranks.
      for io in ompio romio321; do
        for dir in "${places[@]}"; do
          OMPI_MCA_io=$io output_case bake "$dir" "$dir/x.bs" \
            "$MPIEXEC" "$NPFLAG" 2 --oversubscribe "$BAKE" "$INPUTS/cube/cube.bs" "${bake_args[@]}" -o "$dir/x.bs"
        done
        [[ -p $work/fifo/x.bs ]] || mkfifo "$work/fifo/x.bs"
        OMPI_MCA_io=$io output_case bake "$work/fifo" "$work/fifo/x.bs" \
          "$MPIEXEC" "$NPFLAG" 2 --oversubscribe "$BAKE" "$INPUTS/cube/cube.bs" "${bake_args[@]}" -o "$work/fifo/x.bs"
      done
    fi
    # Stale temporaries: a dead run's is removed, a live process's and a directory kept.
    mkdir -p "$work/stale"
    sh -c 'exit 0' &
    dead=$!
    wait "$dead"
    while kill -0 "$dead" 2>/dev/null; do sleep 0.1; done
    out=$work/stale/x.png
    [[ $app == bake ]] && out=$work/stale/x.bsb
    echo stale >"$out.tmp.$dead"
    echo live >"$out.tmp.$$"
    mkdir "$out.tmp.1"
    "${run[@]}" --summary "$work/stale/x.json" -o "$out" >/dev/null 2>&1 || fail "the stale-temporary run failed"
    [[ ! -e $out.tmp.$dead ]] || fail "the dead run's temporary $out.tmp.$dead was kept"
    [[ -f $out.tmp.$$ && -d $out.tmp.1 ]] || fail "a live process's temporary or a directory was removed"
    echo "ok: stale temporaries"
    ;;
  corrupt)
    app=$1
    hash_of() { tail -n 1 "$1" | sed -n 's/.*verification \([0-9a-f]*\)$/\1/p'; }
    # mutate SRC DST HOW [DATASET]: DST = SRC with one bit of DATASET's bytes flipped
    # (HOW=flip), cut to half its size (HOW=truncate), or byte DATASET (an offset) inverted.
    mutate() {
      "$PY" - "$@" <<'PYEOF'
import sys
src, dst, how = sys.argv[1:4]
data = bytearray(open(src, "rb").read())
if how == "flip":
    import h5py
    with h5py.File(src, "r") as f:
        d = f[sys.argv[4]].id
        offset, size = d.get_offset(), d.get_storage_size()
    data[offset + size // 2] ^= 0x10
elif how == "truncate":
    data = data[: len(data) // 2]
else:
    data[int(sys.argv[4])] ^= 0xFF
open(dst, "wb").write(data)
PYEOF
    }
    if [[ $app == sketchtrace ]]; then
      run=("$SKETCH" "$INPUTS/two_spheres/two_spheres.toml" "${sketch_args[@]}" --chunk-pixels 500)
      "${run[@]}" >full.txt
      rc=0
      "${run[@]}" --checkpoint ck.h5 --stop-after-chunks 2 >stop.txt 2>&1 || rc=$?
      [[ $rc == 4 ]] || fail "the stopped run gave exit $rc"
      datasets=(/pixels/done /pixels/raw)
    else
      run=("$BAKE" "$INPUTS/cube/cube.bs" "${bake_args[@]}" --iterations 3 -o out.bs)
      "${run[@]}" >full.txt 2>/dev/null
      rc=0
      "${run[@]}" --checkpoint ck.h5 --stop-after-iteration 1 >stop.txt 2>&1 || rc=$?
      [[ $rc == 4 ]] || fail "the stopped run gave exit $rc"
      datasets=(/colors)
    fi
    full=$(hash_of full.txt)
    [[ -n $full ]] || fail "no hash in the uninterrupted run"
    # Reproducers the fuzz targets found (tests/fuzz): libhdf5 over-reads a heap buffer on
    # one, cannot close itself after the other (two more lines on stderr at exit). Refused
    # with exit 2 and nothing on stderr but the one line, before libhdf5 parses them.
    for f in "$BAD"/h5_*.h5; do
      expect_one_line "$app" 2 "$(basename "$f")" "${run[@]}" --restart "$f"
      [[ $(wc -l <err.txt) == 1 ]] || { cat err.txt >&2; fail "more than one line on stderr: $f"; }
    done
    have_h5py || { echo "note: $PY has no h5py: the per-dataset bit flips are left out"; datasets=(); }
    for d in "${datasets[@]}"; do
      mutate ck.h5 bad.h5 flip "$d"
      expect_one_line "$app" 2 "bad.h5" "${run[@]}" --restart bad.h5
    done
    mutate ck.h5 bad.h5 truncate
    expect_one_line "$app" 2 "bad.h5" "${run[@]}" --restart bad.h5
    size=$(stat -c %s ck.h5)
    refused=0 harmless=0
    for k in $(seq 0 31); do
      mutate ck.h5 bad.h5 byte $((k * size / 32 + 7))
      rc=0
      timeout -k 5 "$limit" "${run[@]}" --restart bad.h5 >out.txt 2>err.txt || rc=$?
      if [[ $rc == 2 ]]; then
        [[ $(grep -c "^$app" err.txt) == 1 ]] || { cat err.txt >&2; fail "byte $k: not one line"; }
        refused=$((refused + 1))
      elif [[ $rc == 0 && $(hash_of out.txt) == "$full" ]]; then
        harmless=$((harmless + 1))
      else
        cat err.txt >&2
        fail "byte $((k * size / 32 + 7)) changed: exit $rc, hash $(hash_of out.txt) (uninterrupted $full)"
      fi
    done
    echo "ok: 32 single-byte changes: $refused refused, $harmless harmless"
    if [[ $app == sketchtrace ]]; then
      "${run[@]}" --balance metric --cost-map cm.h5 >/dev/null
      if have_h5py; then
        mutate cm.h5 bad_cm.h5 flip /cost
        expect_one_line sketchtrace 2 "bad_cm.h5" "${run[@]}" --balance metric --cost-map bad_cm.h5
      fi
      mutate cm.h5 bad_cm.h5 truncate
      expect_one_line sketchtrace 2 "bad_cm.h5" "${run[@]}" --balance metric --cost-map bad_cm.h5
    fi
    ;;
  memory)
    app=$1
    np=$2
    case $app in
      sketchtrace) run=("$SKETCH" "$INPUTS/two_spheres/two_spheres.toml" "${sketch_args[@]}" -o out.png) ;;
      bake) run=("$BAKE" "$INPUTS/cube/cube.bs" "${bake_args[@]}" -o out.bs) ;;
      bake-ao) run=("$BAKE" ao "$INPUTS/meshes/spot.obj" -o out.ply) ;;
      bake-render)
        "$BAKE" "$INPUTS/cube/cube.bs" "${bake_args[@]}" -o map.bs >/dev/null 2>&1 || fail "no map to render"
        run=("$BAKE" render map.bs --width 64 --height 48 -o out.png)
        ;;
    esac
    launch=()
    ((np > 1)) && launch=("$MPIEXEC" "$NPFLAG" "$np" --oversubscribe)
    expect_one_line "${app%%-*}" 3 \
      "needs ~[0-9.e+-]+ GiB on rank 0, 0.000977 GiB available \(--max-memory\); --max-memory overrides" \
      "${launch[@]}" "${run[@]}" --max-memory 1MiB
    [[ ! -e out.png && ! -e out.bs && ! -e out.ply ]] || fail "a refused run wrote its output"
    # The same run without a limit, and with 'unlimited', goes through.
    "${launch[@]}" "${run[@]}" --max-memory unlimited >/dev/null 2>&1 || fail "--max-memory unlimited failed"
    "${launch[@]}" "${run[@]}" >/dev/null 2>&1 || fail "the run failed its check against the machine"
    ;;
  estimate)
    app=$1
    case $app in
      sketchtrace) run=("$SKETCH" "$INPUTS/meshes/stanford-bunny.obj" --width 640 --height 480 --spp 1 -o out.png) ;;
      bake) run=("$BAKE" "$INPUTS/cornell_big/cornell_big_raw.bs" --viewpoints 300 -o out.bs) ;;
      bake-ao) run=("$BAKE" ao "$INPUTS/meshes/dragon.obj") ;;
      bake-render)
        "$BAKE" "$INPUTS/cornell_big/cornell_big_raw.bs" -o map.bs >/dev/null 2>&1 || fail "no map to render"
        run=("$BAKE" render map.bs --width 1280 --height 720 -o out.png)
        ;;
      bench) run=("$BENCH" "$INPUTS/meshes/stanford-bunny.obj" --workload ao --samples-per-face 2 --rays 8 --repeats 1) ;;
      gen) run=("$GEN" bunny --scene "$INPUTS/meshes/stanford-bunny.obj" -o out.bs) ;;
    esac
    "${run[@]}" --summary s.json >out.txt 2>&1 || { cat out.txt; fail "the run failed"; }
    "$PY" - s.json <<'PYEOF' || fail "estimate too far from the peak"
import json, sys
s = json.load(open(sys.argv[1]))
est, peak = s["scene"]["memory_estimate_bytes"], s["peak_memory_bytes"]
print(f"estimate {est / 2**20:.1f} MiB, peak resident {peak / 2**20:.1f} MiB, ratio {est / peak:.2f}")
sys.exit(0 if 0.75 <= est / peak <= 1.5 else 1)
PYEOF
    ;;
  restart_inputs)
    app=$1
    hash_of() { tail -n 1 "$1" | sed -n 's/.*verification \([0-9a-f]*\)$/\1/p'; }
    # change_byte FILE: one byte of FILE changed in place (the last digit of its first vertex,
    # or in an MTL file the first letter of its first comment), still a valid file.
    change_byte() {
      "$PY" - "$1" <<'PYEOF'
import sys
data = bytearray(open(sys.argv[1], "rb").read())
if sys.argv[1].endswith(".mtl"):
    i = data.index(b"#") + 2
    data[i] ^= 0x20
else:
    start = data.index(b"\nv ") + 1
    i = data.index(b"\n", start) - 1
    while not chr(data[i]).isdigit():
        i -= 1
    data[i] = ord("2") if data[i] != ord("2") else ord("3")
open(sys.argv[1], "wb").write(data)
PYEOF
    }
    if [[ $app == sketchtrace ]]; then
      cp -r "$INPUTS/two_spheres" scene
      run=("$SKETCH" scene/two_spheres.toml "${sketch_args[@]}" --chunk-pixels 500)
      stop=(--stop-after-chunks 2)
      changed=(scene/floor.obj)
    else
      mkdir scene
      cp "$INPUTS/meshes/CornellBox-Original.obj" "$INPUTS/meshes/CornellBox-Original.mtl" scene/
      run=("$BAKE" scene/CornellBox-Original.obj "${bake_args[@]}" --iterations 2 -o out.bs)
      stop=(--stop-after-iteration 1)
      changed=(scene/CornellBox-Original.mtl scene/CornellBox-Original.obj)
    fi
    "${run[@]}" >full.txt 2>/dev/null || fail "the uninterrupted run failed"
    rc=0
    "${run[@]}" --checkpoint ck.h5 "${stop[@]}" >stop.txt 2>&1 || rc=$?
    [[ $rc == 4 && -f ck.h5 ]] || fail "the stopped run gave exit $rc and no checkpoint"
    "${run[@]}" --restart ck.h5 >resumed.txt 2>&1 || { cat resumed.txt; fail "the unchanged restart failed"; }
    [[ $(hash_of resumed.txt) == "$(hash_of full.txt)" ]] || fail "the resumed run's hash differs"
    echo "ok: unchanged inputs resume to the uninterrupted hash $(hash_of full.txt)"
    for f in "${changed[@]}"; do
      cp "$f" "$f.orig"
      change_byte "$f"
      cmp -s "$f" "$f.orig" && fail "no byte of $f changed"
      expect_one_line "$app" 2 "$f: content changed since the checkpoint ck.h5 was written" \
        "${run[@]}" --restart ck.h5
      mv "$f.orig" "$f"
    done
    ;;
  places)
    app=$1
    if [[ $app == sketchtrace ]]; then
      run=("$SKETCH" "$INPUTS/two_spheres/two_spheres.toml" "${sketch_args[@]}")
      computed="rendered|pixels to render"
    else
      run=("$BAKE" "$INPUTS/cube/cube.bs" "${bake_args[@]}")
      computed="map per rank|bake time"
    fi
    dirs=("$work/missing_dir")
    if try_mount "$work/ro" ro,size=64k; then
      dirs+=("$work/ro")
    else
      echo "SKIP read-only directory: mounting a tmpfs is not allowed here"
    fi
    for dir in "${dirs[@]}"; do
      for flag in --checkpoint -o; do
        name=x.h5
        [[ $flag == -o ]] && name=x.png && [[ $app == bake ]] && name=x.bs
        expect_one_line "$app" 3 "$(basename "$dir")" "${run[@]}" "$flag" "$dir/$name"
        if grep -Eq "$computed" out.txt; then fail "$flag into $dir was refused only after computing"; fi
      done
    done
    # One file named for two outputs (spelled two ways): exit 2 before anything is computed, and
    # neither output written.
    out=x.png
    [[ $app == bake ]] && out=x.bs
    expect_one_line "$app" 2 "two outputs" "${run[@]}" -o "$out" --summary "./$out"
    if grep -Eq "$computed" out.txt; then fail "the shared output path was refused only after computing"; fi
    [[ ! -e $out ]] || fail "$out was written although the run was refused"
    ;;
  signal)
    app=$1
    # A start-up that takes a while: a large mesh to read and build.
    if [[ $app == sketchtrace ]]; then
      run=("$SKETCH" "$INPUTS/meshes/dragon.obj" --width 320 --height 240 --spp 4 --checkpoint ck.h5)
    else
      run=("$BAKE" "$INPUTS/cornell_big/cornell_big_raw.bs" --viewpoints 1000 --iterations 3 --checkpoint ck.h5 -o out.bs)
    fi
    # Launched from Python: a background job of this (non-interactive) shell would start with
    # SIGINT ignored; Python's child starts with the default action, as from a terminal.
    rc=0
    "$PY" - "${run[@]}" <<'PYEOF' || rc=$?
import signal, subprocess, sys, time
p = subprocess.Popen(sys.argv[1:], stdout=open("out.txt", "w"), stderr=open("err.txt", "w"))
time.sleep(0.3)
p.send_signal(signal.SIGINT)
code = p.wait()
sys.exit(code if code >= 0 else 128 - code)
PYEOF
    cat err.txt
    [[ $rc == 4 ]] || fail "SIGINT during start-up gave exit $rc, expected 4 (a clean stop)"
    [[ -f ck.h5 ]] || fail "no checkpoint after the stop"
    echo "ok: SIGINT at 0.3 s: exit 4 with a checkpoint"
    ;;
  *)
    fail "unknown mode $mode"
    ;;
esac
