#!/usr/bin/python3
"""Session 45: per run directory, whether each round's first learn push was on the object it chose
(ground_truth.class_learn_blobs), and its drift (the object pushed most is not the chosen one).
usage: first_push45.py DIR ...  (DIR/motion-sS.json). Standard library only."""
import json,sys,glob,collections
for d in sys.argv[1:]:
  c=collections.Counter()
  for f in sorted(glob.glob(d+'/motion-s*.json')):
    g=json.load(open(f))['ground_truth']
    for r,ch in enumerate(g['class_chosen']):
      lb=g['class_learn_blobs'][r] if r<len(g['class_learn_blobs']) else []
      if not lb: c['no learn pushes']+=1; continue
      first=lb[0].split('+')[0].split(':')[0]
      c['first learn push on chosen' if first==ch else 'first learn push on another']+=1
      ro=g['round_object'][r]
      if ro!=ch: c['drift (pushed-most != chosen)']+=1
  print(d, dict(c))
