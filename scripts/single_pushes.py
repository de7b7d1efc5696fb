#!/usr/bin/python3
"""Single pushes of one object alone on the simulated table, and whether it still stands after
(ground truth, scoring only; docs/results/selfsupervision-history.md session 29).

usage: PYTHONPATH=build/python scripts/single_pushes.py OBJECTS SEEDS ANGLES [roll|no] [TIP]
  OBJECTS  catalogue names, comma-separated
  SEEDS    table seeds (where the object is put), comma-separated
  ANGLES   push directions, degrees from the object's own x axis (the giraffe's body, the bike's
           wheel line), comma-separated
  roll     the robot turns the jaws across the push (TableOptions.roll_across); default no
  TIP      the pusher tip's height above the table, m (default 0.008, the planner's)
Each push goes through the object's origin (its centre) from 12 cm behind it to 4 cm beyond it at
5 cm/s; one JSON line per push: upright and on_table after, how far it moved (m), or the error
(pushes the arm's inverse kinematics refuses).
"""
import json
import math
import sys

import numpy as np

import proprio.sim as s

objs = sys.argv[1].split(",")
seeds = [int(x) for x in sys.argv[2].split(",")]
angles = [float(x) for x in sys.argv[3].split(",")]
roll = len(sys.argv) > 4 and sys.argv[4] == "roll"
tip = float(sys.argv[5]) if len(sys.argv) > 5 else 0.008
for ob in objs:
    for seed in seeds:
        for d in angles:
            r = s.SimulatedRobot(
                s.TableOptions(objects=1, seed=seed, width=160, height=120, roll_across=roll), [ob])
            g = r.ground_truth()[0]
            c = np.array(g["position"][:2])
            a = g["yaw"] + math.radians(d)
            u = np.array([math.cos(a), math.sin(a)])
            row = {"object": ob, "seed": seed, "angle": d, "roll_across": roll, "tip": tip}
            try:
                r.push(c - 0.12 * u, c + 0.04 * u, height=tip, speed=0.05)
                g2 = r.ground_truth()[0]
                row.update(upright=g2["upright"], on_table=g2["on_table"],
                           moved=round(float(np.linalg.norm(np.array(g2["position"][:2]) - c)), 3))
            except Exception as e:  # the arm refused the push (inverse kinematics)
                row["error"] = str(e)[:160]
            print(json.dumps(row), flush=True)
            r.close()
