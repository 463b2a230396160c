import sys
# rewrite rooms_P.bs's light quad (last 4 positions) to cover only room 0's skylight area
src, dst = sys.argv[1], sys.argv[2]
lines = open(src).read().split("\n")
blank = lines.index("")
pos = lines[:blank]
y = float(pos[-1].split()[1])
w = 0.06 * 99
pos[-4:] = [f"0 {y} 0", f"{w} {y} 0", f"{w} {y} {w}", f"0 {y} {w}"]
open(dst, "w").write("\n".join(pos + lines[blank:]))
