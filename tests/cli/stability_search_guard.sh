#!/usr/bin/env bash
# The stability searches run the runaway guard in report mode: a runaway makes a trial unstable ("runaway" as the
# reason) and the search goes on, exit 0, instead of the guard stopping the program. Here the Fig. 10a search of `bench
# bullet` runs on drop-bunnies.json with the tightest guard the keys allow (every factor 1), so the unstable trials are
# caught by the guard before the energy criterion, and sound trials still pass.
set -uo pipefail
source "$(dirname "$0")/lib.sh"

skip_without simulate "built without the Bullet plugin"
"$tool" --help | grep -qE "^ +bench " || { echo "skipped: built without the bench command"; exit 0; }
mkdir -p "$work/scenes"
python3 - "$assets" "$work/scenes/drop-bunnies.json" <<'PY' || fail "could not write the scene"
import json, sys
assets, out = sys.argv[1], sys.argv[2]
scene = json.load(open(assets + "/scenes/drop-bunnies.json"))
for body in scene["bodies"]:
    if "mesh" in body and body["mesh"].startswith("assets/"):
        body["mesh"] = assets + "/" + body["mesh"][len("assets/"):]
scene["guard"] = {"energy_factor": 1, "max_speed": 1, "extent_factor": 1, "action": "stop"}
json.dump(scene, open(out, "w"))
PY
"$tool" bench bullet --quick --part fig10a --scenes "$work/scenes" --cache "$work/cache" --out "$work/f.csv" \
  > "$work/out.txt" 2> "$work/err.txt" || fail "the search stopped (exit $?): $(cat "$work/err.txt")"
grep -q "runaway guard" "$work/out.txt" || fail "the criterion does not mention the guard"
grep -qE "UNSTABLE .* runaway$" "$work/out.txt" || fail "no trial counted unstable through the guard: $(cat "$work/out.txt")"
grep -qE ": stable " "$work/out.txt" || fail "the guard made every trial unstable: $(cat "$work/out.txt")"
grep -q "^largest stable timestep" "$work/out.txt" || fail "the search did not finish"
echo "ok"
