import json, sys, os
# usage: pooled.py OUT (OUT/pdef, OUT/pcol: the --pooled-score runs); session 38
R=sys.argv[1]
rows=[]
for s in (1,7,8):
    for st in ('pdef','pcol'):
        f=f'{R}/{st}/motion-s{s}.json'
        if not os.path.exists(f): print(s, st, 'unfinished'); continue
        g=json.load(open(f))['ground_truth']
        p={(x['weight'],x['once']):x for x in g['pooled']}
        cells=' | '.join(f"{100*p[(w,False)]['accuracy']:.1f}" for w in (0.0,0.25,0.5,0.75,1.0))
        po=' '.join(f"{100*v:.0f}" for v in p[(1.0,False)]['per_object'])
        print(f"| {s} | {st} | {100*g['mot_accuracy']:.1f} | {cells} | {po} |")
