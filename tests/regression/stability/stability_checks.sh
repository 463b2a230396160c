#!/bin/bash
# Stability at the extremes (issue 7), one case per ctest (label stability, CMakeLists.txt here).
#   sketch_bounces     white/grey furnace box, 0 and 1000 bounces, ambient or emission up to
#                      1e6: finite image, mean = the closed form (exactly where noise-free);
#                      a coarse sphere stays finite and below its bound
#   bake_iterations    mirror furnace box: K = 0 and 1000, rho = 1 exactly (E (K + 1)) and
#                      rho = 0.5 with emission 1e6 (E (1 - rho^(K+1)) / (1 - rho)), all finite
#   bake_viewpoints    N = 1, 2, 7 and 100000 viewpoints: runs, memory estimate printed, every
#                      viewpoint colour equals the furnace value (N = 1: within its bounds)
#   sketch_sizes       1x1 renders; 16384x16384 prints its estimate and is refused by --max-memory
#   general_kernel     bundled scenes: --general-kernel gives the same verification hash as the
#                      lean instantiation each runs (two_spheres at 4 and 8 shadow samples:
#                      shafts compiled in, unused and used; spheres and dist_first: glossy lobes)
#   nonfinite_input    NaN/Inf in an OBJ, a .bs and scene TOMLs: exit 2, "file:line: reason"
# Environment: BAKE, SKETCH, GEN (rtmini-gen-inputs), INPUTS, DATA (tests/data/bad).
# Usage: stability_checks.sh CASE WORKDIR
set -u
case_name=$1
work=$2
rm -rf "$work"
mkdir -p "$work"
cd "$work" || exit 1

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# Every viewpoint colour of a .bs equals `expected` within relative tolerance `tol`.
check_all_colours() {
  awk -v e="$2" -v tol="$3" '/^\|/ { for (i = 5; i <= 7; i++) { d = ($i - e) / e; if (d < 0) d = -d;
      if (d > max || d != d) max = d } n++ }
    END { printf "%d viewpoint lines, max relative error %.3g (tolerance %g)\n", n, max, tol;
      exit (n == 0 || max > tol || max != max) }' "$1"
}

# The image statistics line of a sketchtrace run: checks finiteness and the mean.
check_image_mean() {  # LOG EXPECTED TOL
  awk -v e="$2" -v tol="$3" '/^  image: mean/ { seen = 1; m = ($3 + $4 + $5) / 3; nf = $(NF - 2)
      d = (m - e) / e; if (d < 0) d = -d
      printf "image mean %.6g, expected %.6g (relative error %.3g, tolerance %g), %d non-finite\n", m, e, d, tol, nf
      bad = (nf != 0 || d > tol || m != m) }
    END { exit (!seen || bad) }' "$1"
}

furnace_toml() {  # FILE ALBEDO EMISSION AMBIENT SHAPE: camera inside a closed box or sphere
  cat >"$1" <<EOF
ambient = [$4, $4, $4]

[settings]
width = 16
height = 16
spp = 4
shadow_samples = 16
indirect = true
smooth = false
sphere_subdivisions = 3
edge_thickness = 0.0

[camera]
position = [0.1, -0.2, 0.3]
look_at = [0.5, 0.1, -0.4]
fov_deg = 90.0

[[materials]]
name = "furnace"
kd = [$2, $2, $2]
ke = [$3, $3, $3]
EOF
  if [[ $5 == box ]]; then
    printf '[[meshes]]\nfile = "%s"\nmaterial = "furnace"\n' "$INPUTS/dist_first/box.obj" >>"$1"
  else
    printf '[[spheres]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = { kd = [%s, %s, %s], ke = [%s, %s, %s] }\n' \
      "$2" "$2" "$2" "$3" "$3" "$3" >>"$1"
  fi
}

case $case_name in
  sketch_bounces)
    # Lit by ambient A only, every path in a closed flat box carries exactly a^k after k
    # diffuse bounces, so each pixel is a A (1 - a^(B+1)) / (1 - a) (a = 1: A (B + 1)) with
    # no noise: an exploding or non-finite path shows at once, lost paths (escapes through
    # the box's edges; measured 3e-5 of the energy at B = 1000) within 1e-3. Then the box as an
    # emitter E = 1e6 (light sampling, noisy): finite, within 10 % of E (1 - a^(B+2)) / (1 - a).
    # shape albedo emission ambient bounces expected-mean tolerance
    while read -r shape a e amb b want tol; do
      furnace_toml f.toml "$a" "$e" "$amb" "$shape"
      "$SKETCH" f.toml --bounces "$b" >log.txt 2>&1 || { cat log.txt; fail "sketchtrace failed (a $a, B $b)"; }
      check_image_mean log.txt "$want" "$tol" ||
        fail "$shape furnace a=$a E=$e A=$amb B=$b off the closed form"
    done <<'EOF'
box 1 0 1 0 1 1e-5
box 1 0 1 1000 1001 1e-3
box 0.5 0 1e6 1000 1e6 1e-3
box 1 0 1e6 1000 1.001e9 1e-3
box 0.5 1e6 0 0 1.5e6 0.1
box 0.5 1e6 0 1000 2e6 0.1
EOF
    # A coarse sphere (1280 triangles) shades with its analytic normal: diffuse directions
    # below the facet are dropped, so energy is lost (about 20 % at 1000 bounces), never gained.
    furnace_toml f.toml 1 0 1 sphere
    "$SKETCH" f.toml --bounces 1000 >log.txt 2>&1 || { cat log.txt; fail "sphere furnace failed"; }
    awk '/^  image: mean/ { m = ($3 + $4 + $5) / 3; nf = $(NF - 2)
        printf "sphere furnace B=1000: mean %.6g, bound 1001\n", m; ok = (nf == 0 && m == m && m > 0 && m <= 1001 * 1.00001) }
      END { exit !ok }' log.txt || fail "sphere furnace not finite or above the closed-form bound"
    ;;
  bake_iterations)
    # rho emission iterations expected-colour
    while read -r rho e k want; do
      "$GEN" furnace --rho "$rho" --emission "$e" --cells 0 -o furnace.bs >/dev/null || fail gen
      "$BAKE" furnace.bs -o out.bs --viewpoints 20 --iterations "$k" >log.txt 2>&1 ||
        { cat log.txt; fail "bake failed (rho $rho, K $k)"; }
      check_all_colours out.bs "$want" 1e-3 || fail "furnace rho=$rho E=$e K=$k off the closed form"
    done <<'EOF'
1 1 0 1
1 1 1000 1001
0.5 1 1000 2
0.5 1e6 1000 2e6
1 1e6 1000 1.001e9
EOF
    ;;
  bake_viewpoints)
    # N = 1 puts the only viewpoint at (1, 0, 0): mirror directions about the corner normals
    # leave the box, so colours lie between E and the closed form; from N = 2 on, the value.
    "$GEN" furnace --rho 0.5 --emission 1 --cells 0 -o furnace.bs >/dev/null || fail gen
    # K = 1 at N = 100000 keeps the case under 20 s: colour E (1 + rho) = 1.5.
    for n in 1 2 7 100000; do
      k=3 want=1.875
      [ "$n" -eq 100000 ] && k=1 want=1.5
      "$BAKE" furnace.bs -o out.bs --viewpoints "$n" --iterations "$k" >log.txt 2>&1 ||
        { cat log.txt; fail "bake failed (N $n)"; }
      grep "memory estimate" log.txt || fail "no memory estimate printed (N $n)"
      lines=$(grep -c '^|' out.bs)
      [ "$lines" -eq $((8 * n)) ] || fail "N $n: $lines viewpoint lines, expected $((8 * n))"
      if [ "$n" -eq 1 ]; then
        awk '/^\|/ { for (i = 5; i <= 7; i++) if (!($i >= 1 && $i <= 1.875)) bad++ }
          END { exit bad > 0 }' out.bs || fail "N 1: a colour outside [E, closed form]"
      else
        check_all_colours out.bs "$want" 1e-5 || fail "N $n: colours off the furnace value"
      fi
    done
    ;;
  sketch_sizes)
    scene=$INPUTS/two_spheres/two_spheres.toml
    "$SKETCH" "$scene" --width 1 --height 1 --spp 4 -o one.ppm >log.txt 2>&1 ||
      { cat log.txt; fail "1x1 render failed"; }
    [ "$(head -c 2 one.ppm)" = "P6" ] || [ "$(head -c 2 one.ppm)" = "P3" ] || fail "no 1x1 image"
    grep -q "non-finite pixels" log.txt || fail "no image statistics"
    grep -q " 0 non-finite pixels" log.txt || fail "1x1 render has a non-finite pixel"
    "$SKETCH" "$scene" --width 16384 --height 16384 --max-memory 1G -o big.ppm >out.txt 2>err.txt
    rc=$?
    cat out.txt err.txt
    [ $rc -eq 3 ] || fail "16K x 16K under --max-memory 1G exited $rc, expected 3"
    grep -q "needs ~.* GiB on rank 0, 1 GiB available (--max-memory)" err.txt ||
      fail "no clear refusal message"
    [ "$(wc -l <err.txt)" -eq 1 ] || fail "expected exactly one line on stderr"
    [ ! -e big.ppm ] || fail "output written despite the refusal"
    # The estimate is at least the frame's pixel results (16384^2 x 48 bytes = 12 GiB).
    gib=$(sed -n 's/.*needs ~\([0-9.]*\) GiB.*/\1/p' err.txt)
    awk -v m="$gib" 'BEGIN { exit !(m > 12) }' || fail "estimate $gib GiB is too small"
    # A limit above the estimate lets the same small render run.
    "$SKETCH" "$scene" --width 8 --height 8 --spp 1 --max-memory 4G >log.txt 2>&1 ||
      { cat log.txt; fail "8x8 render under --max-memory 4G failed"; }
    "$SKETCH" "$scene" --width 8 --height 8 --max-memory 12X >out.txt 2>err.txt
    [ $? -eq 2 ] || fail "bad --max-memory unit not refused with exit 2"
    echo "1x1 renders; 16K refused after a ${gib} GiB estimate"
    ;;
  general_kernel)
    for run in two_spheres:4 two_spheres:8 spheres:4 dist_first:1; do
      scene=${run%:*}
      args=("$INPUTS/$scene/$scene.toml" --width 64 --height 48 --spp 2 --shadow-samples "${run#*:}")
      "$SKETCH" "${args[@]}" >spec.txt 2>&1 || { cat spec.txt; fail "$scene specialised failed"; }
      "$SKETCH" "${args[@]}" --general-kernel >gen.txt 2>&1 || { cat gen.txt; fail "$scene general failed"; }
      grep -q "forced general kernel" gen.txt || fail "$scene: --general-kernel had no effect"
      grep "kernel features" spec.txt gen.txt
      h1=$(tail -n 1 spec.txt | awk '{print $NF}')
      h2=$(tail -n 1 gen.txt | awk '{print $NF}')
      [[ -n $h1 && $h1 == "$h2" ]] || fail "$scene: hash $h1 (specialised) vs $h2 (general)"
      echo "$scene: identical hash $h1"
    done
    ;;
  nonfinite_input)
    expect_bad() {  # LABEL FILE-PATTERN COMMAND...: exit 2 and one "file:line: reason" line
      local label=$1 pattern=$2
      shift 2
      "$@" >out.txt 2>err.txt
      local rc=$?
      cat err.txt
      [ $rc -eq 2 ] || fail "$label: exit $rc, expected 2"
      grep -Eq "$pattern" err.txt || fail "$label: stderr does not match '$pattern'"
    }
    expect_bad "obj nan" "obj_nan_vertex.obj:3: .*non-finite" "$SKETCH" "$DATA/obj_nan_vertex.obj"
    expect_bad "bs nan" "bs_nan.bs:2: .*non-finite" "$BAKE" "$DATA/bs_nan.bs" -o out.bs
    expect_bad "bs inf material" "bs_material_inf.bs:[0-9]+: .*non-finite" \
      "$BAKE" "$DATA/bs_material_inf.bs" -o out.bs
    expect_bad "toml nan" "toml_nan_number.toml:[0-9]+: .*finite" "$SKETCH" "$DATA/toml_nan_number.toml"
    expect_bad "toml inf" "toml_inf_vector.toml:[0-9]+: .*finite" "$SKETCH" "$DATA/toml_inf_vector.toml"
    expect_bad "toml float overflow" "toml_float_overflow.toml:[0-9]+: " \
      "$SKETCH" "$DATA/toml_float_overflow.toml"
    expect_bad "settings nan" "toml_settings_nan.toml:[0-9]+: .*finite" \
      "$SKETCH" "$DATA/toml_settings_nan.toml"
    expect_bad "ao toml nan" "toml_ao_nan_translate.toml:[0-9]+: .*finite" \
      "$BAKE" --mode ao "$DATA/toml_ao_nan_translate.toml" -o out.bin
    [[ ! -e out.bs && ! -e out.bin ]] || fail "output written for a bad input"
    ;;
  *)
    fail "unknown case $case_name"
    ;;
esac
