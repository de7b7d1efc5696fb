"""Summary of the session-21 runs (as session 20's): python3 summary.py DIR N SEED... (DIR holds
motN-sSEED.json): mean class accuracy % per seed, mean +- t interval, per-object recall, the
mixture's confusion (by words) summed over the seeds; the seeds whose JSON is missing (a run
stopped for time) are named and left out. PAIR=OTHER_DIR: the paired differences (this DIR minus
OTHER_DIR, seed by seed, on the seeds both have) with their t interval."""
import os
import json,sys,glob,statistics as st,math
T975={1:12.71,2:4.30,3:3.18,4:2.78,5:2.57,6:2.45,7:2.36,8:2.31,9:2.26}
def g(run,theta,model,comp=10):
    for x in run['mot_grid']:
        if x['theta']==theta and x['prior']=='views' and x.get('model')==model and x.get('components',10)==comp and x['smoothing']==0: return x
def ci(v):
    m=st.mean(v); 
    if len(v)<2: return f"{m:.1f}"
    s=st.stdev(v); return f"{m:.1f} +- {T975[len(v)-1]*s/math.sqrt(len(v)):.1f} (sd {s:.1f})"
name,n=sys.argv[1],sys.argv[2]; seeds=sys.argv[3:]
M={'argmax':lambda r:r['classes'],'words':lambda r:g(r,'estep','mixture-words'),'wpost':lambda r:g(r,'word-posterior','mixture'),'5nn-words':lambda r:[c for c in r.get('ceilings',[]) if c['name']=='knn-words'][0]}
res={k:[] for k in M}; per={k:[] for k in M}; conf=None; tv=[]
missing=[s for s in seeds if not os.path.exists(f'{name}/mot{n}-s{s}.json')]
if missing: print(f"missing (not finished): seeds {' '.join(missing)}")
seeds=[s for s in seeds if s not in missing]
if not seeds: sys.exit(0)
for s in seeds:
    d=json.load(open(f'{name}/mot{n}-s{s}.json')); r=d['runs'][0]; tv.append(d['test_views'])
    for k,f in M.items():
        try: x=f(r)
        except Exception: continue
        res[k].append(100*x['mean_class_accuracy'])
        per[k].append([100*row[i]/max(1,sum(row)+u) for i,(row,u) in enumerate(zip(x['counts'],x['unclassified']))])
    c=g(r,'estep','mixture-words')['counts']
    conf=c if conf is None else [[a+b for a,b in zip(x,y)] for x,y in zip(conf,c)]
cols=d['objects']
print(f"{name} {n} objects, seeds {' '.join(seeds)}, test views {tv}")
for k in M:
    if not res[k]: continue
    print(f"  {k:10s} " + ' '.join(f"{v:.1f}" for v in res[k]) + "  mean " + ci(res[k]))
    print("     per object: " + ', '.join(f"{o} {st.mean(p[i] for p in per[k]):.1f} ({min(p[i] for p in per[k]):.0f}-{max(p[i] for p in per[k]):.0f})" for i,o in enumerate(cols)))
for k in ('words','wpost'):
    if res[k]: print(f"  {k} above argmax: {sum(a>b for a,b in zip(res[k],res['argmax']))} of {len(seeds)}; at or above 92.5: {sum(a>=92.5 for a in res[k])}")
print("  confusion (words, summed; rows truth):", cols, conf)

other=os.environ.get('PAIR')
if other:
    both=[s for s in seeds if os.path.exists(f'{other}/mot{n}-s{s}.json')]
    for k in ('argmax','words','wpost'):
        diffs=[]
        for s in both:
            a=M[k](json.load(open(f'{name}/mot{n}-s{s}.json'))['runs'][0])
            b=M[k](json.load(open(f'{other}/mot{n}-s{s}.json'))['runs'][0])
            diffs.append(100*(a['mean_class_accuracy']-b['mean_class_accuracy']))
        if diffs: print(f"  paired {k} minus {other} (seeds {' '.join(both)}): " + ' '.join(f"{v:+.1f}" for v in diffs) + "  mean " + ci(diffs))
