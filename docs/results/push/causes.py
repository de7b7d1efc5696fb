#!/usr/bin/python3
"""Why pushes moved another object: per executed table, each push's other objects moved (> 5 mm)
and when the arm touched them (transit/push/return; none: the pushed object or a chain did)."""
import json, sys, collections
for path in sys.argv[1:]:
    d = json.load(open(path))
    rows = [r for r in d['pushes'] if r['final_distance'] is not None]
    bad = [r for r in rows if not r['only_intended']]
    print(f"{path}: executed {len(rows)}, not only-intended {len(bad)}, median {d['median_distance']*1000:.1f} mm, only {d['only_intended_rate']:.2f}, refused {d['refused']}, not planned {d['not_planned']}, not seen {d['not_seen']}")
    causes = collections.Counter()
    first_step = collections.Counter()
    for r in bad:
        tags = set()
        for k, s in enumerate(r['steps']):
            for o in s.get('others', []):
                if o['moved'] <= 0.005: continue
                t = o['touch'] or 'object'
                tags.add(t)
                first_step[k] += 1
        for t in tags: causes[t] += 1
        if not tags: causes['(intended did not move?)'] += 1
        print(f"  seed {r['seed']} {r['object']}: " + " | ".join(
            (f"step{k}{' via' if s.get('via') else ''} clr {s.get('start_clearance',0)*1000:.0f}mm blk {s.get('blocked',0)*1000:.0f}: " +
             ", ".join(f"{o['name']} {o['moved']*1000:.0f}mm {o['touch'] or '-'}" for o in s.get('others', [])))
            for k, s in enumerate(r['steps']) if s['executed']))
    print("  causes (tables):", dict(causes), "by step:", dict(first_step))
    vias = sum(1 for r in rows for s in r['steps'] if s.get('via'))
    print("  via pushes:", vias)
