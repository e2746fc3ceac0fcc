#!/usr/bin/env bash
# Certifies tracers that are not octrace's kernel on the committed meshes and the bunny, and
# prints the table of docs/CERTIFY.md: Embree in its default mode (--backend embree-fast), the
# textbook Moller-Trumbore of examples/moller_trumbore.py, and for comparison octrace's linear
# layout and Embree's robust mode (the reference itself).
# Usage: examples/third_party.sh [OUTDIR]   (OCTRACE=path/to/octrace, default build/octrace;
#        COUNT seeded rays per mesh, default 20000; SIZE of the camera set, default 128x128)
set -euo pipefail
cd "$(dirname "$0")/.."
octrace="${OCTRACE:-build/octrace}"
out="${1:-$(mktemp -d)}"
count="${COUNT:-20000}"
size="${SIZE:-128x128}"
python=/usr/bin/python3  # Debian's, with python3-numpy
mkdir -p "$out"
meshes=(meshes/*.obj meshes/*.ply meshes/*.off meshes/*.stl)
[ -f meshes/cache/bunny.obj ] && meshes+=(meshes/cache/bunny.obj)

summary() {  # one table row from a certify JSON report
  "$python" - "$1" "$2" "$3" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
r = j["result"]
sets = r["by_set"]
def cell(name):
    s = sets[name]
    return f'{s["wrong"]}/{s["ambiguous"]}' + (f'/{s["leaks"]}' if s["leak_checked"] else "")
closed = "closed" if j["scene"]["topology"]["closed"] else "open"
print(f'| {sys.argv[2]} ({closed}) | {sys.argv[3]} | {j["correct"]} | {j["watertight"]} | '
      f'{r["wrong"]} | {r["leaks"]} | ' + " | ".join(cell(n) for n in r["sets"]) + " |")
EOF
}

echo "| mesh | tracer | correct | watertight | wrong | leaks | camera | shadow | around | inside |" \
     "axis | edges | vertices | grazing | tmin-tmax |"
echo "|---|---|---|---|---:|---:|---|---|---|---|---|---|---|---|---|"
for m in "${meshes[@]}"; do
  name=$(basename "$m")
  d="$out/$name"
  mkdir -p "$d"
  "$octrace" rays "$m" --count "$count" --size "$size" --seed 1 --out "$d/R.npy" \
      --triangles "$d/T.npy" >/dev/null
  "$octrace" trace "$m" --rays "$d/R.npy" --out "$d/linear" --backend cpu --accel linear >/dev/null
  "$octrace" trace "$m" --rays "$d/R.npy" --out "$d/embree" --backend embree >/dev/null
  "$octrace" trace "$m" --rays "$d/R.npy" --out "$d/embree-fast" --backend embree-fast >/dev/null
  "$python" examples/moller_trumbore.py "$d/T.npy" "$d/R.npy" "$d/mt" >/dev/null
  for t in linear embree embree-fast mt; do
    "$octrace" certify "$m" --rays "$d/R.npy" --hits "$d/$t" --json "$d/$t.json" \
        >"$d/$t.txt" 2>&1 || true
    summary "$d/$t.json" "$name" "$t"
  done
done
echo "reports in $out" >&2
