#!/usr/bin/python3
"""Paired tables of two evaluate-push JSONs: final distance better / worse (by > 2 mm) / same.
Usage: paired.py A.json B.json"""
import json, sys
a = {t['seed']: t for t in json.load(open(sys.argv[1]))['pushes']}
b = {t['seed']: t for t in json.load(open(sys.argv[2]))['pushes']}
better = worse = same = 0
for s in sorted(set(a) & set(b)):
    x, y = a[s].get('final_distance'), b[s].get('final_distance')
    if x is None or y is None or x < 0 or y < 0:
        continue
    if y < x - 0.002: better += 1
    elif y > x + 0.002: worse += 1
    else: same += 1
print(f"{sys.argv[2]} against {sys.argv[1]}: better {better}, worse {worse}, within 2 mm {same}")
