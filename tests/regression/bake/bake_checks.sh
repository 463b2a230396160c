#!/bin/bash
# Regression checks of the bake app, one case per ctest (tests/regression/bake/CMakeLists.txt).
# Environment: BAKE, GEN (rtmini-gen-inputs), RUN1/RUN2/RUN4 style launchers are built from
# MPIEXEC and NPFLAG; INPUTS (inputs/), REF (tests/reference/bake), BAD (tests/data/bad);
# HOST_REFERENCES=0 on a device backend, whose bytes are not the committed host hashes.
# Usage: bake_checks.sh CASE WORKDIR [RANKS]
set -u
case_name=$1
work=$2
ranks=${3:-1}
mkdir -p "$work"
cd "$work" || exit 1
rm -f ./*.bs ./*.bsb ./*.h5 ./*.txt ./*.json

run() {  # run N ARGS...: bake on N ranks
  local n=$1
  shift
  if [ -n "${MPIEXEC:-}" ]; then
    "$MPIEXEC" "$NPFLAG" "$n" --oversubscribe "$BAKE" "$@"
  else
    "$BAKE" "$@"
  fi
}

# Two copies of the seed's closed cube (8 vertices, the ceiling a light), 10 apart along x, with
# mirror walls (Kr 0.3): no ray leaves its cube.
two_cubes() {
  local dx
  for dx in 0 10; do
    for v in "-1 -1 -1" "1 -1 -1" "-1 1 -1" "1 1 -1" "-1 -1 1" "1 -1 1" "-1 1 1" "1 1 1"; do
      read -r x y z <<<"$v"
      echo "$((x + dx)) $y $z"
    done
  done
  printf '\n: 0.6 0.6 0.6  0.3 0.3 0.3  0 0 0\n: 0 0 0  0 0 0  1 1 1\n\n'
  local o
  for o in 0 8; do
    echo "$((0 + o)) $((1 + o)) $((3 + o)) $((2 + o)) 0"
    echo "$((4 + o)) $((6 + o)) $((7 + o)) $((5 + o)) 0"
    echo "$((0 + o)) $((4 + o)) $((5 + o)) $((1 + o)) 0"
    echo "$((2 + o)) $((3 + o)) $((7 + o)) $((6 + o)) 1"
    echo "$((0 + o)) $((2 + o)) $((6 + o)) $((4 + o)) 0"
    echo "$((1 + o)) $((5 + o)) $((7 + o)) $((3 + o)) 0"
  done
  echo "!"
}

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# Every viewpoint colour equals `expected` within relative tolerance `tol`.
check_all_colours() {
  awk -v e="$2" -v tol="$3" '/^\|/ { for (i = 5; i <= 7; i++) { d = ($i - e) / e; if (d < 0) d = -d;
      if (d > max) max = d } n++ }
    END { printf "%d viewpoint lines, max relative error %.3g (tolerance %g)\n", n, max, tol;
      exit (n == 0 || max > tol) }' "$1"
}

# json_error SUMMARY KEY: the value of errors.KEY in a --summary file (KEY may be a.b).
json_error() {
  python3 -c 'import json, sys
value = json.load(open(sys.argv[1]))["errors"]
for key in sys.argv[2].split("."):
    value = value[key]
print(value)' "$1" "$2"
}

case $case_name in
  regenerate)
    # The committed generated inputs equal a fresh generation.
    "$GEN" cube -o cube.bs >/dev/null || fail "generator failed"
    cmp cube.bs "$INPUTS/cube/cube.bs" || fail "cube.bs differs"
    "$GEN" cornell_big -o big.bs >/dev/null || fail "generator failed"
    cmp big.bs "$INPUTS/cornell_big/cornell_big_raw.bs" || fail "cornell_big_raw.bs differs"
    [ "$(grep -c '^[-0-9]' big.bs)" -gt 0 ] || fail "empty cornell_big"
    "$GEN" cornell --scene "$INPUTS/meshes/CornellBox-Original.obj" -o cb.bs >/dev/null ||
      fail "generator failed"
    cmp cb.bs "$INPUTS/cornell/cornell_box.bs" || fail "cornell_box.bs differs"
    echo "generated inputs match the committed ones"
    ;;
  furnace)
    # E = 1, rho = 0.5, K = 3: every colour 1 * (1 - 0.5^4) / (1 - 0.5) = 1.875.
    for cells in 0 3; do
      "$GEN" furnace --rho 0.5 --emission 1 --cells $cells -o furnace.bs >/dev/null || fail gen
      run "$ranks" furnace.bs -o out.bs --viewpoints 60 --iterations 3 >log.txt 2>&1 ||
        { cat log.txt; fail "bake failed"; }
      check_all_colours out.bs 1.875 1e-5 || fail "furnace (cells $cells) off the analytic value"
    done
    ;;
  reference)
    # Cornell box (shared scene, .bs copy): file hash against the committed reference.
    run "$ranks" "$INPUTS/cornell/cornell_box.bs" -o out.bs --viewpoints 40 --iterations 3 \
      --shadow-samples 16 --seed 7 >log.txt 2>&1 || { cat log.txt; fail "bake failed"; }
    got=$(sha256sum out.bs | cut -d' ' -f1)
    want=$(cut -d' ' -f1 "$REF/cornell_box_n40_k3.sha256")
    [ "$got" = "$want" ] || fail "cornell_box output sha256 $got, reference $want"
    tail -n 1 log.txt
    echo "sha256 matches the reference ($ranks ranks)"
    ;;
  decomposition)
    # Any batch size, balance and lookup on $ranks ranks gives the bytes of a 1-rank run; so does
    # --progress, which cuts rank 0's batches into pieces to report between (kitchen.cpp).
    args=("$INPUTS/cornell_big/cornell_big_raw.bs" --viewpoints 100 --iterations 4 --gather-rays 4)
    run 1 "${args[@]}" -o one.bs >log1.txt 2>&1 || { cat log1.txt; fail "1-rank bake failed"; }
    run "$ranks" "${args[@]}" -o many.bs --batch-size 157 --balance cost --lookup sf --progress \
      >log2.txt 2>progress.txt || { cat log2.txt progress.txt; fail "$ranks-rank bake failed"; }
    cmp one.bs many.bs || fail "outputs differ between 1 and $ranks ranks"
    [ "$(tail -n 1 log1.txt | awk '{print $NF}')" = "$(tail -n 1 log2.txt | awk '{print $NF}')" ] ||
      fail "verification hashes differ"
    grep -q '^bake: \[#*\] 100.0%' progress.txt || { cat progress.txt; fail "--progress drew no final line"; }
    echo "byte-identical for 1 and $ranks ranks (batch 157, cost balance, sf lookup, --progress)"
    ;;
  hemisphere)
    # --directions hemisphere (one-sided mirrors keep the front N/2 viewpoints, each vertex in its
    # own frame): the file hash against its committed reference; $ranks ranks with the other
    # lookup give the bytes of 1 rank; a checkpoint of $ranks ranks restarts on another rank
    # count; the header marks the layout and bake render reads both forms alike; --two-sided and
    # an odd N are refused with exit 2.
    args=("$INPUTS/cornell/cornell_box.bs" --viewpoints 40 --iterations 3 --shadow-samples 16
      --seed 7 --directions hemisphere)
    other=$((ranks == 1 ? 2 : ranks - 1))
    run 1 "${args[@]}" -o one.bs >log1.txt 2>&1 || { cat log1.txt; fail "1-rank bake failed"; }
    got=$(sha256sum one.bs | cut -d' ' -f1)
    if [ "${HOST_REFERENCES:-1}" = 1 ]; then
      want=$(cut -d' ' -f1 "$REF/cornell_box_n40_k3_hemisphere.sha256")
      [ "$got" = "$want" ] || fail "hemisphere output sha256 $got, reference $want"
    else
      echo "device backend: the reference hash is the host's; checking ranks and restart only"
    fi
    [ "$(head -n 1 one.bs)" = "# hemisphere" ] || fail "no '# hemisphere' header line"
    awk '/^\|/ { n++ } /^[-0-9]/ && !faces { if (n && n != 20) bad = 1; n = 0 } /^$/ { faces = 1 }
      END { exit bad }' one.bs || fail "a vertex does not have N/2 = 20 viewpoint lines"
    run "$ranks" "${args[@]}" --lookup sf -o many.bs --summary many.json >log2.txt 2>&1 ||
      { cat log2.txt; fail "$ranks-rank bake failed"; }
    cmp one.bs many.bs || fail "outputs differ between 1 rank (kdtree) and $ranks ranks (sf)"
    run "$ranks" "${args[@]}" -o part.bs --checkpoint cp.h5 --stop-after-iteration 1 >log3.txt 2>&1
    [ $? -eq 4 ] || { cat log3.txt; fail "stop after iteration 1 did not exit 4"; }
    run "$other" "${args[@]}" -o part.bs --checkpoint cp.h5 --restart cp.h5 >log4.txt 2>&1 ||
      { cat log4.txt; fail "restart on $other ranks failed"; }
    cmp one.bs part.bs || fail "checkpoint of $ranks ranks restarted on $other ranks differs"
    run 1 "${args[@]:0:9}" -o sphere.bs --restart cp.h5 >log5.txt 2>err5.txt
    [ $? -eq 2 ] || fail "a hemisphere checkpoint restarted as a sphere bake did not exit 2"
    run 1 "${args[@]}" -o one.bsb >log6.txt 2>&1 || fail "binary bake failed"
    "$BAKE" render one.bs -o a.ppm --width 48 --height 36 >log7.txt 2>&1 ||
      { cat log7.txt; fail "render of the hemisphere .bs failed"; }
    "$BAKE" render one.bsb -o b.ppm --width 48 --height 36 >log8.txt 2>&1 ||
      { cat log8.txt; fail "render of the hemisphere .bsb failed"; }
    cmp a.ppm b.ppm || fail ".bs and .bsb hemisphere maps render differently"
    # The owner-computes map with its sparse halo (viewpoint masks over N/2) on the gridded box.
    big=("$INPUTS/cornell_big/cornell_big_raw.bs" --viewpoints 60 --iterations 3 --directions hemisphere)
    run 1 "${big[@]}" -o big1.bs >log11.txt 2>&1 || { cat log11.txt; fail "cornell_big bake failed"; }
    run "$ranks" "${big[@]}" -o big2.bs --balance spatial >log12.txt 2>&1 ||
      { cat log12.txt; fail "cornell_big bake on $ranks ranks failed"; }
    cmp big1.bs big2.bs || fail "cornell_big hemisphere outputs differ between 1 and $ranks ranks"
    run 1 "${args[@]}" --two-sided -o x.bs >log9.txt 2>err9.txt
    [ $? -eq 2 ] || fail "--two-sided hemisphere not refused (exit 2)"
    grep -q "one-sided" err9.txt || fail "--two-sided refusal does not give the reason"
    run 1 "${args[@]}" --viewpoints 41 -o x.bs >log10.txt 2>err10.txt
    [ $? -eq 2 ] || fail "odd N hemisphere not refused (exit 2)"
    echo "hemisphere map: reference hash, identical on 1 and $ranks ranks, restart on $other ranks"
    ;;
  distributed)
    # Owner-computes map, mirror rays only (the traced halo): $ranks ranks give the bytes and the
    # hash of 1 rank, each rank holds less than the whole map, and a checkpoint written on
    # $ranks ranks restarts on another rank count with another ownership (--balance spatial).
    args=("$INPUTS/cornell_big/cornell_big_raw.bs" --viewpoints 60 --iterations 3 --lookup sf)
    other=$((ranks == 1 ? 2 : ranks - 1))
    run 1 "${args[@]}" -o one.bs --summary one.json >log1.txt 2>&1 || { cat log1.txt; fail "1-rank bake failed"; }
    run "$ranks" "${args[@]}" -o many.bs --summary many.json >log2.txt 2>&1 ||
      { cat log2.txt; fail "$ranks-rank bake failed"; }
    cmp one.bs many.bs || fail "outputs differ between 1 and $ranks ranks"
    grep -E "map per rank|work per rank" log2.txt
    # Two closed mirror cubes apart, a cube's vertices per rank at 2 ranks: a rank whose colours
    # no other rank reads sends nothing in the changed-only exchanges (it once crashed there).
    two_cubes >cubes.bs
    run 1 cubes.bs --viewpoints 20 --iterations 4 -o cubes1.bs >log11.txt 2>&1 ||
      { cat log11.txt; fail "1-rank bake of two cubes failed"; }
    run "$ranks" cubes.bs --viewpoints 20 --iterations 4 -o cubes.out.bs >log12.txt 2>&1 ||
      { cat log12.txt; fail "$ranks-rank bake of two cubes failed"; }
    cmp cubes1.bs cubes.out.bs || fail "two cubes: outputs differ between 1 and $ranks ranks"
    # The same with node sharing and per-rank maps (the layout across nodes), the first rank
    # late: the others take the pieces of a rank that reads no remote vertex in the first
    # iteration (it once crashed there).
    run "$ranks" cubes.bs --viewpoints 20 --iterations 4 -o cubes.shared.bs --node-sharing on \
      --node-map off --share-test-delay 0.3 >log13.txt 2>&1 ||
      { cat log13.txt; fail "$ranks-rank shared bake of two cubes failed"; }
    cmp cubes1.bs cubes.shared.bs || fail "two cubes, node sharing: outputs differ from 1 rank"
    # The pilot's cut (no recut after the trace, no hits moved) gives the same bytes.
    run "$ranks" "${args[@]}" -o pilot.bs --balance pilot --summary pilot.json >log5.txt 2>&1 ||
      { cat log5.txt; fail "$ranks-rank bake with --balance pilot failed"; }
    cmp one.bs pilot.bs || fail "--balance pilot differs from 1 rank"
    # Full exchanges every iteration (the default sends only changed colours): the same bytes.
    run "$ranks" "${args[@]}" -o full.bs --exchange full --summary full.json \
      >log9.txt 2>&1 || { cat log9.txt; fail "$ranks-rank bake with full exchanges failed"; }
    cmp one.bs full.bs || fail "--exchange full differs from 1 rank"
    # The measured recut after iteration 1, from a skew that makes it move work for certain
    # (rank r taken as 1 + r times slower than counted), and from the measured times. The first
    # reads the node's one copy of the scene (--node-sharing scene, which allows the recut).
    run "$ranks" "${args[@]}" -o skew.bs --balance measured --recut-test-skew 1 --summary skew.json \
      --node-sharing scene >log7.txt 2>&1 ||
      { cat log7.txt; fail "$ranks-rank bake with a skewed measured recut failed"; }
    cmp one.bs skew.bs || fail "--balance measured (skewed recut) differs from 1 rank"
    grep -E "measured recut" log7.txt
    run "$ranks" "${args[@]}" -o measured.bs --balance measured >log8.txt 2>&1 ||
      { cat log8.txt; fail "$ranks-rank bake with --balance measured failed"; }
    cmp one.bs measured.bs || fail "--balance measured differs from 1 rank"
    run "$ranks" "${args[@]}" -o part.bs --checkpoint cp.h5 --stop-after-iteration 1 >log3.txt 2>&1
    [ $? -eq 4 ] || { cat log3.txt; fail "stop after iteration 1 did not exit 4"; }
    run "$other" "${args[@]}" -o part.bs --checkpoint cp.h5 --restart cp.h5 --balance spatial \
      --progress >log4.txt 2>&1 || { cat log4.txt; fail "restart on $other ranks failed"; }
    cmp one.bs part.bs || fail "checkpoint of $ranks ranks restarted on $other (spatial) differs"
    # The same restart with the default cut: it recuts after the trace and moves the hits. With
    # node work sharing, which starts at its first iteration (the traced hits, then the cache).
    run "$other" "${args[@]}" -o part2.bs --restart cp.h5 --node-sharing on >log6.txt 2>&1 ||
      { cat log6.txt; fail "restart on $other ranks (cost) failed"; }
    cmp one.bs part2.bs || fail "checkpoint of $ranks ranks restarted on $other (cost) differs"
    # Node sharing (--node-sharing on): one copy of the scene, and the ranks take each other's
    # pieces in the mirror trace and the iterations; the node's first rank starts each 0.3 s
    # late, so the others take its pieces. With the node's one map (the default on one node) and
    # with per-rank maps and halos (--node-map off, the layout across nodes).
    run "$ranks" "${args[@]}" -o shared.bs --node-sharing on --share-test-delay 0.3 \
      --summary shared.json >log10.txt 2>&1 || { cat log10.txt; fail "$ranks-rank shared bake failed"; }
    cmp one.bs shared.bs || fail "--node-sharing on differs from 1 rank"
    run "$ranks" "${args[@]}" -o shared_halo.bs --node-sharing on --node-map off \
      --share-test-delay 0.3 --summary shared_halo.json >log14.txt 2>&1 ||
      { cat log14.txt; fail "$ranks-rank shared bake with --node-map off failed"; }
    cmp one.bs shared_halo.bs || fail "--node-sharing on --node-map off differs from 1 rank"
    # Across nodes: the test hook cuts this machine into nodes of two ranks (and one at 3 ranks).
    # Node sharing within each node, the trace per rank and the recut after it, the first rank
    # late (its node-mate takes its pieces); each node's one map with halos of the other nodes'
    # colours, and per-rank maps with halos (--node-map off).
    if [ "$ranks" -ge 3 ]; then
      for layout in on off; do
        RTMINI_TEST_RANKS_PER_NODE=2 run "$ranks" "${args[@]}" -o "nodes_$layout.bs" \
          --node-sharing on --node-map "$layout" --share-test-delay 0.3 \
          --summary "nodes_$layout.json" >"log15_$layout.txt" 2>&1 ||
          { cat "log15_$layout.txt"; fail "$ranks-rank bake on nodes of two ranks (--node-map $layout) failed"; }
        cmp one.bs "nodes_$layout.bs" || fail "nodes of two ranks, --node-map $layout: differs from 1 rank"
      done
    fi
    # Bad input before any work: an unknown value, and the measured recut (it moves vertices
    # between ranks after iteration 1, node sharing balances within each iteration).
    for bad in "--node-sharing yes" "--node-sharing work --balance measured" "--node-map yes"; do
      # shellcheck disable=SC2086
      run "$ranks" "${args[@]}" -o bad.bs $bad >/dev/null 2>bad_err.txt
      rc=$?
      [ $rc -eq 2 ] || { cat bad_err.txt; fail "$bad exited $rc, expected 2"; }
      [ "$(grep -c '^bake: ' bad_err.txt)" -eq 1 ] || { cat bad_err.txt; fail "$bad: not one line"; }
    done
    /usr/bin/python3 - "$ranks" <<'PY' || fail "summary"
import json, sys
r = int(sys.argv[1])
one, many = json.load(open("one.json")), json.load(open("many.json"))
assert one["verification_hash"] == many["verification_hash"]
m = many["scene"]["map"]
colors = many["scene"]["colors"]
print("local colours max", m["local_colors_max"], "of", colors, "remote reads", m["remote_read_fraction"],
      "exchange bytes/iteration", m["exchange_bytes_per_iteration"], "peak RSS per rank",
      many["scene"]["peak_rss_bytes_per_rank"])
if r > 1:
    assert m["halo"] == "traced", m
    assert m["local_colors_max"] < colors, (m, colors)
    assert m["exchange_bytes_per_iteration"] > 0
    changed = m["exchange_changed_fraction"]
    full = json.load(open("full.json"))["scene"]["map"]["exchange_changed_fraction"]
    print("changed-only exchanges: fraction of the halo colours sent", changed, "(full:", full, ")")
    assert 0 <= changed < 1 and full == 1, (changed, full)
# Work counters: every rank's, and the counted cut balances the modelled iteration cost at least
# as well as the pilot's estimate (both are deterministic for this input).
pilot = json.load(open("pilot.json"))
w, wp = many["scene"]["work"], pilot["scene"]["work"]
for k in ("items", "trace_nodes", "lookups", "remote_reads", "iteration_cost"):
    assert len(w[k]["per_rank"]) == r, (k, w[k])
    print("work", k, "max/mean: cost %.3f, pilot %.3f" % (w[k]["max_over_mean"], wp[k]["max_over_mean"]))
assert sum(w["items"]["per_rank"]) == sum(wp["items"]["per_rank"]) == colors
# Both cuts are capped at --max-colors 1.1 (the default) x the mean colours per rank, but for one
# vertex; under the cap the counted cut no longer always beats the pilot's (np4: 1.140 / 1.131).
n = many["parameters"]["stored_viewpoints"]
for s in (w, wp):
    assert s["items"]["max"] <= 1.1 * s["items"]["mean"] + n, s["items"]
# Under the cap the counted cut still balances the iteration cost (within kCostTolerance, 2 %,
# of the mean, or pieces of equal cost swapped between ranks; here 1.001-1.017): a rank may own
# several ranges, and the output above is the same for any of them.
assert w["iteration_cost"]["max_over_mean"] <= 1.03, w["iteration_cost"]
print("ranges per rank", many["scene"]["map"].get("ranges_per_rank"))
# Node work sharing: from iteration 1 (the fused halo plan's), the late first rank's pieces taken
# by the others, every colour entry computed once.
for name in ("shared.json", "shared_halo.json") if r > 1 else ():
    sh = json.load(open(name))["scene"]["node_shared_work"]
    print(name, "node sharing:", sh)
    assert sh["from_iteration"] == 1 and sh["ranks_per_node"] == r, sh
    stolen = sh["stolen_items_per_rank"]
    assert stolen[0] == 0 and sum(stolen[1:]) > 0, sh
    assert sum(stolen) <= 3 * colors, (stolen, colors)  # three shared iterations (1 to 3)
# The node's one map: each rank holds its own vertices' part, reads the rest in place, exchanges
# nothing; with --node-map off a halo refreshed by exchanges.
if r > 1:
    node, halo = (json.load(open(n))["scene"]["map"] for n in ("shared.json", "shared_halo.json"))
    print("node map:", node["halo"], node["local_colors_max"], node["exchange_bytes_per_iteration"],
          "per-rank maps:", halo["halo"], halo["local_colors_max"], halo["exchange_bytes_per_iteration"])
    assert node["halo"] == "node" and node["node_map"] and node["exchange_bytes_per_iteration"] == 0, node
    items = json.load(open("shared.json"))["scene"]["work"]["items"]["per_rank"]
    assert node["local_colors_max"] == max(items) < colors, (node, items)
    assert halo["halo"] == "traced" and halo["exchange_bytes_per_iteration"] > 0, halo
    sh = json.load(open("shared.json"))["scene"]["node_shared_work"]
    # The mirror trace shared too (one node, no recut after it): the late first rank's pieces
    # traced by the others into its records, each colour entry's ray traced once.
    traced = sh["trace_stolen_items_per_rank"]
    assert sh["trace_shared"] and 0 < sum(traced[1:]) and sum(traced) <= colors, sh
    # The work counters stay the cut's: each rank's trace rays and nodes, whoever traced them.
    shared_work = json.load(open("shared.json"))["scene"]["work"]
    for k in ("trace_rays", "trace_nodes"):
        assert shared_work[k]["per_rank"] == w[k]["per_rank"], (k, shared_work[k], w[k])
    # Each rank's share of the node's memory (PSS), where its RSS also counts the pages of other
    # ranks' segments that it read.
    pss = json.load(open("shared.json"))["scene"]["max_pss_after_step_bytes_per_rank"]
    assert len(pss) == r and min(pss) > 0, pss
    # One copy of the scene per node, with the work sharing and alone.
    scene = json.load(open("skew.json"))["scene"]["node_shared_work"]
    assert sh["scene_bytes_per_node"] > 0 and scene["scene_bytes_per_node"] == sh["scene_bytes_per_node"], (sh, scene)
# Nodes of two ranks: sharing within each (rank 1 takes the late rank 0's pieces), the trace per
# rank and the recut (hits moved); with each node's one map the exchanges move only the other
# nodes' colours: fewer bytes than between per-rank maps.
if r >= 3:
    exchanged = {}
    for layout in ("on", "off"):
        nd = json.load(open("nodes_%s.json" % layout))["scene"]
        sh, m = nd["node_shared_work"], nd["map"]
        print("nodes of two ranks, --node-map", layout, sh, m["halo"], m["exchange_bytes_per_iteration"])
        assert sh["ranks_per_node"] == 2 and not sh["trace_shared"], sh
        assert (min(sh["node_map_bytes_per_rank"]) > 0) == (layout == "on") == m["node_map"], sh
        assert sh["stolen_items_per_rank"][1] > 0, sh
        assert m["halo"] == "traced" and m["exchange_bytes_per_iteration"] > 0, m
        assert sum(nd["work"]["moved_hits"]["per_rank"]) > 0, nd["work"]["moved_hits"]
        exchanged[layout] = m["exchange_bytes_per_iteration"]
    assert exchanged["on"] < exchanged["off"], exchanged
# The skewed recut: rank r measured as 1 + r times its counted cost, so the cut gives the later
# ranks less counted cost than the earlier ones and moves colours.
if r > 1:
    rc = json.load(open("skew.json"))["scene"]["recut"]
    print("skewed recut: moved", rc["moved_colors"], "colours,", rc["bytes"], "bytes, cost after",
          rc["counted_cost_after_per_rank"])
    assert rc["moved_colors"] > 0 and rc["bytes"] > 0, rc
    after = rc["counted_cost_after_per_rank"]
    assert after[0] > after[-1], rc
    assert abs(sum(after) - sum(rc["counted_cost_before_per_rank"])) < 1e-6 * sum(after), rc
PY
    echo "owner-computes map: identical on 1 and $ranks ranks, restart on $other ranks"
    ;;
  restart)
    # Stop after iteration 1 (exit 4, checkpoint), restart, compare with an uninterrupted run.
    args=("$INPUTS/cornell_big/cornell_big_raw.bs" --viewpoints 60 --iterations 4)
    run "$ranks" "${args[@]}" -o full.bs >log1.txt 2>&1 || fail "full run failed"
    run "$ranks" "${args[@]}" -o part.bs --checkpoint cp.h5 --stop-after-iteration 1 >log2.txt 2>&1
    rc=$?
    [ $rc -eq 4 ] || fail "stopped run exited $rc, expected 4"
    [ ! -e part.bs ] || fail "stopped run left an output file"
    run "$ranks" "${args[@]}" -o part.bs --checkpoint cp.h5 --restart cp.h5 >log3.txt 2>&1 ||
      { cat log3.txt; fail "restart failed"; }
    cmp full.bs part.bs || fail "restarted output differs"
    # A checkpoint for other parameters is refused with exit 2.
    run "$ranks" "$INPUTS/cornell_big/cornell_big_raw.bs" --viewpoints 61 --iterations 4 \
      -o other.bs --restart cp.h5 >log4.txt 2>err.txt
    rc=$?
    [ $rc -eq 2 ] || fail "mismatched restart exited $rc, expected 2"
    # The checkpoint of the last iteration holds the output's colours in the file's viewpoint
    # order (the iterations keep another, view_order.hpp). Every vertex view-dependent: N
    # checkpoint colours each, so the two line up without the scene's materials.
    run "$ranks" "${args[@]}" --all-view-dependent -o last.bsb --checkpoint last.h5 >log5.txt 2>&1 ||
      fail "checkpointed .bsb run failed"
    if /usr/bin/python3 -c "import h5py" 2>/dev/null; then
      /usr/bin/python3 - <<'PY' || fail "the last checkpoint is not the output map"
import struct
import h5py, numpy as np
raw = open("last.bsb", "rb").read()
flags, V, M, F, O, D, C = struct.unpack_from("<I6Q", raw, 4)
assert flags & 3 == 1, "expected shared directions and float32 colours"
at = lambda n: (n + 7) // 8 * 8
p = at(64 + V * (24 if flags & 4 else 12))
counts = np.frombuffer(raw, "<u4", V, p)
p = at(p + 4 * V)
uniform = np.frombuffer(raw, "u1", V, p).astype(bool)
p = at(at(p + V) + D * 12)
colours = np.frombuffer(raw, "<f4", 3 * C, p).reshape(C, 3)
assert (counts == D).all()
per_vertex = np.where(uniform, 1, D)
first = np.concatenate(([0], np.cumsum(per_vertex)[:-1]))
slot = first[:, None] + np.where(uniform[:, None], 0, np.arange(D)[None, :])
cp = h5py.File("last.h5", "r")["/colors"][()].reshape(V, D, 3)
assert (cp == colours[slot]).all(), "colours differ"
varying = (~uniform).sum()
assert varying >= 100, varying  # cornell_big_raw: 470 of 1,924
print(f"last checkpoint = output map ({V} vertices, {varying} with varying colours)")
PY
    fi
    echo "restart reproduces the uninterrupted output ($ranks ranks)"
    ;;
  kill)
    # SIGKILL once the first checkpoint exists, restart, compare.
    args=("$INPUTS/cornell_big/cornell_big_raw.bs" --viewpoints 1500 --iterations 6 --no-hit-cache)
    "$BAKE" "${args[@]}" -o full.bs >log1.txt 2>&1 || fail "full run failed"
    "$BAKE" "${args[@]}" -o part.bs --checkpoint cp.h5 >log2.txt 2>&1 &
    pid=$!
    for _ in $(seq 1 600); do
      [ -e cp.h5 ] && break
      sleep 0.05
    done
    kill -9 $pid 2>/dev/null
    wait $pid 2>/dev/null
    [ -e cp.h5 ] || fail "no checkpoint appeared"
    [ ! -e part.bs ] || echo "note: the run finished before the kill"
    "$BAKE" "${args[@]}" -o part.bs --checkpoint cp.h5 --restart cp.h5 >log3.txt 2>&1 ||
      { cat log3.txt; fail "restart failed"; }
    grep "restart:" log3.txt
    cmp full.bs part.bs || fail "output after SIGKILL + restart differs"
    if ls ./*.tmp.* 2>/dev/null; then fail "temporary files left behind"; fi
    echo "SIGKILL + restart reproduces the uninterrupted output"
    ;;
  timings)
    run "$ranks" "$INPUTS/cornell_big/cornell_big_raw.bs" -o out.bs --viewpoints 50 --iterations 2 \
      --batch-size 300 --timings t.h5 --summary s.json >log.txt 2>&1 || fail "bake failed"
    # The layout is read with h5py; a machine without it (the CUDA host) reports a skip.
    /usr/bin/python3 -c "import h5py" 2>/dev/null ||
      { echo "skipped: the run passed; /usr/bin/python3 has no h5py to read t.h5"; exit 77; }
    /usr/bin/python3 - "$ranks" <<'PY' || fail "timings layout"
import json, sys
import h5py
r = int(sys.argv[1])
f = h5py.File("t.h5", "r")
assert f.attrs["ranks"] == r, f.attrs["ranks"]
assert f["iterations/trace_time"].shape == (r, 3), f["iterations/trace_time"].shape
assert f["iterations/allgather_bytes"].shape == (r, 3)
names = [n.decode() for n in f["phases/names"][:]]
assert names == ["read", "setup", "base", "map", "halo", "iterate", "write"], names
assert f["phases/start"].shape == (r, len(names))
assert len(f["chunks/rank"]) == 7 * 3, len(f["chunks/rank"])  # 1924 / 300 -> 7 batches
assert sorted(set(f["chunks/rank"][:])) == list(range(r))
s = json.load(open("s.json"))
assert s["app"] == "bake" and s["ranks"] == r and len(s["verification_hash"]) == 16
print("timings and summary layout ok")
PY
    ;;
  bad)
    # $3 is the kind of bad input; exit 2, exactly one line on stderr, no output file.
    case $ranks in
      malformed) args=("$BAD/bs_nan.bs") ;;
      missing_bang) args=("$BAD/bs_missing_bang.bs") ;;
      zero_viewpoints) args=("$INPUTS/cube/cube.bs" --viewpoints 0) ;;
      negative_iterations) args=("$INPUTS/cube/cube.bs" --iterations -1) ;;
      zero_shadow_samples) args=("$INPUTS/cube/cube.bs" --shadow-samples 0) ;;
      bad_lookup) args=("$INPUTS/cube/cube.bs" --lookup octree) ;;
      reference_vertices)
        # A baked cube (8 vertices) as the reference of another scene.
        "$BAKE" "$INPUTS/cube/cube.bs" -o ref.bs --viewpoints 10 >/dev/null 2>&1 || fail "cube bake"
        args=("$INPUTS/cornell/cornell_box.bs" --viewpoints 10 --reference ref.bs)
        ;;
      reference_uneven)
        # A baked cube whose first vertex lost a viewpoint line.
        "$BAKE" "$INPUTS/cube/cube.bs" -o full.bs --viewpoints 10 >/dev/null 2>&1 || fail "cube bake"
        awk 'NR != 2' full.bs >ref.bs
        args=("$INPUTS/cube/cube.bs" --viewpoints 10 --reference ref.bs)
        ;;
      reference_raw) args=("$INPUTS/cube/cube.bs" --reference "$INPUTS/cube/cube.bs") ;;
      trace_reference_gather) args=("$INPUTS/cube/cube.bs" --trace-reference --gather-rays 4) ;;
      *) fail "unknown bad-input kind $ranks" ;;
    esac
    "$BAKE" "${args[@]}" -o out.bs >out.txt 2>err.txt
    rc=$?
    cat err.txt
    [ $rc -eq 2 ] || fail "exit $rc, expected 2"
    [ "$(wc -l <err.txt)" -eq 1 ] || fail "expected exactly one line on stderr"
    grep -q '^bake: ' err.txt || fail "message does not start with 'bake: '"
    [ ! -e out.bs ] || fail "output file left behind"
    if ls out.bs.tmp.* 2>/dev/null; then fail "temporary file left behind"; fi
    echo "exit 2, one line, no output file"
    ;;
  map_errors_self)
    # A map compared with itself has no error (stored colours, viewpoint by viewpoint);
    # another seed's map has some. The traced reference is byte-identical for 1 and $ranks ranks.
    args=("$INPUTS/cornell/cornell_box.bs" --viewpoints 40 --iterations 3 --shadow-samples 16)
    run "$ranks" "${args[@]}" --seed 7 -o map.bs >log1.txt 2>&1 || { cat log1.txt; fail "bake"; }
    run "$ranks" "${args[@]}" --seed 7 -o again.bs --reference map.bs --summary self.json \
      >log2.txt 2>&1 || { cat log2.txt; fail "bake --reference"; }
    grep 'reference map.bs' log2.txt
    [ "$(json_error self.json stored.entries)" = 2880 ] || fail "expected 72 x 40 entries"
    [ "$(json_error self.json reference_viewpoints)" = 40 ] || fail "expected reference N = 40"
    for key in mean_abs rmse rel_mse max_abs; do
      [ "$(json_error self.json stored.$key)" = 0.0 ] ||
        fail "self error $key = $(json_error self.json stored.$key)"
    done
    run "$ranks" "${args[@]}" --seed 8 -o other.bs --reference map.bs --summary other.json \
      >log3.txt 2>&1 || { cat log3.txt; fail "bake --seed 8 --reference"; }
    awk -v e="$(json_error other.json stored.rmse)" 'BEGIN { exit !(e > 0) }' ||
      fail "another seed's map has no error"
    run 1 "${args[@]}" --trace-reference -o ref1.bs >log4.txt 2>&1 || { cat log4.txt; fail "ref"; }
    run "$ranks" "${args[@]}" --trace-reference -o refn.bs >log5.txt 2>&1 ||
      { cat log5.txt; fail "ref on $ranks ranks"; }
    cmp ref1.bs refn.bs || fail "traced reference differs between 1 and $ranks ranks"
    echo "self error 0, seed 8 RMSE $(json_error other.json stored.rmse), reference identical on $ranks ranks"
    ;;
  map_errors_converge)
    # Against one traced reference of N = 1000 (same base colours: same seed and shadow
    # samples), the Cornell box map read along the reference's directions gets closer to it
    # as its own N grows.
    args=("$INPUTS/cornell/cornell_box.bs" --iterations 2 --shadow-samples 16 --seed 7)
    "$BAKE" "${args[@]}" --viewpoints 1000 --trace-reference -o ref.bs >ref.txt 2>&1 ||
      { cat ref.txt; fail "traced reference"; }
    last=""
    for n in 20 100 1000; do
      "$BAKE" "${args[@]}" --viewpoints $n -o "map$n.bs" --reference ref.bs --summary "s$n.json" \
        >"map$n.txt" 2>&1 || { cat "map$n.txt"; fail "bake N = $n"; }
      e=$(json_error "s$n.json" rmse)
      echo "N = $n: RMSE $e, view-dependent RMSE $(json_error "s$n.json" view_dependent_rmse)"
      if [ -n "$last" ]; then
        awk -v a="$e" -v b="$last" 'BEGIN { exit !(a < b) }' || fail "error did not fall at N = $n"
      fi
      last=$e
    done
    ;;
  binary)
    # -o X.bsb writes the binary form of the very map -o X.bs writes as text: both load to
    # the identical mesh (the unit test, given the two files) and render identically.
    [ -n "${BSB_UNIT:-}" ] || fail "BSB_UNIT (rtmini_unit_bsb) not given"
    args=("$INPUTS/cornell_big/cornell_big_raw.bs" --viewpoints 60 --iterations 2 --seed 3)
    run "$ranks" "${args[@]}" -o map.bs >log1.txt 2>&1 || { cat log1.txt; fail "bake -o .bs failed"; }
    run "$ranks" "${args[@]}" -o map.bsb >log2.txt 2>&1 || { cat log2.txt; fail "bake -o .bsb failed"; }
    [ "$(tail -n 1 log1.txt | awk '{print $NF}')" = "$(tail -n 1 log2.txt | awk '{print $NF}')" ] ||
      fail "verification hashes differ"
    head -c 4 map.bsb | grep -q '^BSB1$' || fail "map.bsb does not start with BSB1"
    # The colours go out in chunks packed from the map (16 MiB by default, one chunk here): tiny
    # chunks, each a few vertices, cut every rank's ranges many times and write the same bytes.
    export RTMINI_BSB_CHUNK_BYTES=2000
    run "$ranks" "${args[@]}" -o chunked.bsb >log3.txt 2>&1 ||
      { cat log3.txt; fail "bake -o .bsb in small chunks failed"; }
    unset RTMINI_BSB_CHUNK_BYTES
    cmp map.bsb chunked.bsb || fail "the binary form written in small chunks differs"
    echo "map.bs $(wc -c <map.bs) bytes, map.bsb $(wc -c <map.bsb) bytes"
    RTMINI_BAKED_BS=$PWD/map.bs RTMINI_BAKED_BSB=$PWD/map.bsb "$BSB_UNIT" \
      --gtest_filter='*BakedTextAndBinaryOutputsAgree*' >unit.txt 2>&1 || { cat unit.txt; fail "maps differ"; }
    grep -q 'PASSED  \] 1 test' unit.txt || { cat unit.txt; fail "the comparison did not run"; }
    for form in bs bsb; do
      "$BAKE" render "map.$form" --width 64 --height 48 -o "img_$form.ppm" >"render_$form.txt" 2>&1 ||
        { cat "render_$form.txt"; fail "bake render map.$form failed"; }
    done
    cmp img_bs.ppm img_bsb.ppm || fail "the two forms render differently"
    echo "text and binary outputs load to the same map ($ranks ranks)"
    ;;
  max_memory)
    "$BAKE" "$INPUTS/cornell_big/cornell_big_raw.bs" -o out.bs --viewpoints 1000 --max-memory 1M \
      >out.txt 2>err.txt
    rc=$?
    cat err.txt
    [ $rc -eq 3 ] || fail "exit $rc, expected 3"
    grep -q "needs ~.* GiB on rank 0, .* available (--max-memory)" err.txt || fail "no clear message"
    [ ! -e out.bs ] || fail "output file left behind"
    ;;
  *)
    fail "unknown case $case_name"
    ;;
esac
