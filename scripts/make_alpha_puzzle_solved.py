#!/usr/bin/env python3
"""Writes assets/scenes/haptics/alpha-puzzle-solved{,-small}.json from the planned disentangling path.

Usage (from the repository root, after building the planner):
  python3 scripts/make_alpha_puzzle_solved.py build/demos/alpha_puzzle_path
The planner (demos/tools/alpha_puzzle_path.cpp) runs with margin 0.003 and thinning 0.01 generator units (seed 1,
deterministic, about 1-8 minutes); its keyframes become the scenes' user script.
"""
import json
import subprocess
import sys

planner = sys.argv[1] if len(sys.argv) > 1 else "build/demos/alpha_puzzle_path"
path = json.loads(subprocess.run([planner, "0.003", "0.01", "0.02", "1.5", "1", "80000"], check=True,
                                 stdout=subprocess.PIPE, text=True).stdout)
# Before the planned path: the hand pulls the piece 8 mm along -x against the static loop (0.3-1.0 s, contact) and
# brings it back (1.0-1.5 s); the planned path (alpha_puzzle_path's keyframes after its first 0.5 s at rest) follows.
start = path[0]
pulled = dict(start, position=[start["position"][0] - 0.008, start["position"][1], start["position"][2]])
keys = [dict(start, t=0.0), dict(start, t=0.3), dict(pulled, t=1.0), dict(start, t=1.5)]
keys += [dict(k, t=round(k["t"] + 1.0, 3)) for k in path[2:]]
def scene(name, desc, resolution, points, offset):
    return {
      "name": name, "description": desc, "poseFrame": "mesh",
      "obstacle": {"mesh": {"procedural": "alpha-puzzle-piece", "scale": 0.02, "resolution": resolution, "padding": 4, "offsetCells": offset}},
      "shell": {"shape": "alpha-puzzle-piece", "scale": 0.02, "points": points, "iterations": 10, "mass": 0.05},
      "start": {"position": keys[0]["position"], "rotationVector": keys[0]["rotationVector"]},
      "script": keys,
      "seconds": keys[-1]["t"],
      "device": {"mass": 0.3, "userStiffness": 200, "userDamping": 8},
      "constraint": {"couplingGain": 0.5, "renderStiffness": 300, "sigmaCells": 0.02, "contactThresholdCells": 0.02, "maxStepCells": 2},
      "penalty": {"stiffness": 200, "damping": 0.0, "couplingStiffness": 2000, "couplingDamping": 10, "maxDisplacementCells": 0.5}
    }
common = ("Paper Section 5 (alpha puzzle), solved: the pieces of alpha-puzzle.json taken apart along a path planned from the generator's geometry "
          "(demos/tools/alpha_puzzle_path.cpp: RRT-Connect on the tubes' centre curves, clearance at least 0.0047 generator units = 0.09 mm on the whole path, shortened, "
          "then pulled straight away until the centres are 1.3 piece lengths apart). The generator's gap where the loop crosses itself is 0.597 between the curves, "
          "0.003 short of a tube diameter (0.6): round tubes could not pass each other (the 24-sided meshes, up to 0.0013 thinner, just can: "
          "without the offset the constraint method slides through the neck in contact). As the paper does for its starter motor "
          "(Fig. 13b: the distance field offset slightly), the static piece's field is offset by -0.2 mm (the tube thinned by 6.7% of its radius: 0.01 generator units), which opens the gap to 0.007 generator units. The hand first pulls the piece against the static loop (0.3-1.5 s, in contact), then follows the path.")
full = scene("alpha-puzzle-solved", common + " 512-cell field (cached with alpha-puzzle.json's), 25,000 points.", 512, 25000, -1.05)
small = scene("alpha-puzzle-solved-small", common + " Test variant: 128-cell field, 3,000 points.", 128, 3000, -0.27)
for s in (full, small):
    with open(f"assets/scenes/haptics/{s['name']}.json", "w") as f:
        f.write(json.dumps(s, indent=2) + "\n")
