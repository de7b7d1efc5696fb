import json,sys,collections
runs=[]
for d,seeds in (("/work/s44/base",range(97,103)),("/work/s44/rbase",range(103,123))):
  for s in seeds: runs.append((s,f"{d}/motion-s{s}.json",f"{d}/motion-s{s}/decisions.jsonl"))
cause=collections.Counter()
for s,j,l in runs:
  d=json.load(open(j)); g=d['ground_truth']
  ev=[json.loads(x) for x in open(l)]
  chosen=g['class_chosen']; ro=g['round_object']; co=g['class_object']
  objs=[o['name'] for o in g['objects']] if isinstance(g['objects'][0],dict) and 'name' in g['objects'][0] else None
  learned=set(); lines=[]
  chooses=[e for e in ev if e['event']=='choose']
  for r in range(len(ro)):
    why=''
    if chosen[r] in learned: why='chose-learned'
    elif ro[r] is None or ro[r]=='' : why='no-views'
    elif ro[r]!=chosen[r]: why=('drift-to-learned' if ro[r] in learned else 'drift-to-new')
    else: why='ok-new'
    # claims at this choice
    sc=[c for c in chooses if c.get('round')==r]
    claim=''
    if sc and sc[-1].get('scores'):
      blobs=g['class_blobs'][r]
      claim=' '.join(f"{blobs[x['blob']] if x['blob']<len(blobs) else '?'}:{x.get('claimed_by')}:{x.get('nearest',0):.2f}" for x in sc[-1]['scores'])
    cause[why]+=1
    lines.append(f"  r{r} chose {chosen[r]} pushed-most {ro[r]} views {d['views_per_class'][r]} stop '{d['stop_reasons'][r]}' -> {why} | {claim}")
    if ro[r]: learned.add(ro[r])
  n=len(set(x for x in co if x))
  print(f"seed {s}: objects with a class {n}")
  if n<4: print("\n".join(lines))
print(cause)
print("by number of choices:")
cc=collections.Counter()
for s,j,l in runs:
  d=json.load(open(j)); g=d['ground_truth']; ev=[json.loads(x) for x in open(l)]
  learned=set()
  for r in range(len(g['round_object'])):
    n=len([e for e in ev if e['event']=='choose' and e.get('round')==r])
    ro=g['round_object'][r]; ch=g['class_chosen'][r]
    why='chose-learned' if ch in learned else ('no-views' if not ro else ('drift' if ro!=ch else 'ok-new'))
    if r>0: cc[(n>1, why)]+=1
    if ro: learned.add(ro)
for k,v in sorted(cc.items()): print(k,v)
