"""Summary of the session-22 runs: python3 summary.py DIR N SEED... (DIR holds motN-sSEED.json
of `experiment scatter --mot-grid-word-weights ...`): per word weight w (0 = the mixture by words
alone), the mean class accuracy % per seed, mean +- t(0.975, n-1) sd / sqrt(n), per-object recall,
how many seeds are above argmax theta and at or above 92.5; the confusion of WEIGHT (default the
first weight found) summed over the seeds; the paired difference of each w minus w = 0. The
mixture is the grid's first component cap (10), fitted on the E-step theta, prior from the views.
Missing seeds (a run stopped for time) are named and left out."""
import json, math, os, statistics as st, sys
T975 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26}


def point(run, model, weight=None):
    for x in run['mot_grid']:
        if (x['theta'] == 'estep' and x['prior'] == 'views' and x.get('model') == model
                and x.get('components', 10) == 10 and x['smoothing'] == 0
                and x.get('word_weight') == weight):
            return x
    raise KeyError(f'{model} {weight}')


def ci(v):
    m = st.mean(v)
    if len(v) < 2:
        return f'{m:.1f}'
    s = st.stdev(v)
    return f'{m:.1f} +- {T975[len(v) - 1] * s / math.sqrt(len(v)):.1f} (sd {s:.1f})'


def recall(x):
    return [100 * row[i] / max(1, sum(row) + u)
            for i, (row, u) in enumerate(zip(x['counts'], x['unclassified']))]


name, n = sys.argv[1], sys.argv[2]
seeds = sys.argv[3:]
missing = [s for s in seeds if not os.path.exists(f'{name}/mot{n}-s{s}.json')]
if missing:
    print(f"missing (not finished): seeds {' '.join(missing)}")
seeds = [s for s in seeds if s not in missing]
if not seeds:
    sys.exit(0)
runs = {}
for s in seeds:
    d = json.load(open(f'{name}/mot{n}-s{s}.json'))
    runs[s] = d['runs'][0]
cols = d['objects']
weights = sorted({x['word_weight'] for x in runs[seeds[0]]['mot_grid'] if 'word_weight' in x})
methods = {'argmax': lambda r: r['classes'], 'w=0 (words)': lambda r: point(r, 'mixture-words')}
for w in weights:
    methods[f'w={w:g}'] = lambda r, w=w: point(r, 'mixture-words-multinomial', w)
methods['naive Bayes'] = lambda r: [c for c in r['ceilings'] if c['name'] == 'naive-bayes-words'][0]
methods['5-NN words'] = lambda r: [c for c in r['ceilings'] if c['name'] == 'knn-words'][0]
print(f"{name}: {n} objects, seeds {' '.join(seeds)}, test views {d['test_views']}")
acc = {}
for k, f in methods.items():
    v = [100 * f(runs[s])['mean_class_accuracy'] for s in seeds]
    acc[k] = v
    per = [recall(f(runs[s])) for s in seeds]
    line = f"  {k:12s} " + ' '.join(f'{x:.1f}' for x in v) + '  mean ' + ci(v)
    if k != 'argmax':
        line += (f"  above argmax {sum(a > b for a, b in zip(v, acc['argmax']))}/{len(seeds)},"
                 f" >= 92.5 {sum(a >= 92.5 for a in v)}/{len(seeds)}")
    print(line)
    print('       per object: ' + ', '.join(
        f'{o} {st.mean(p[i] for p in per):.1f} ({min(p[i] for p in per):.0f}-{max(p[i] for p in per):.0f})'
        for i, o in enumerate(cols)))
for w in weights:
    k = f'w={w:g}'
    diffs = [a - b for a, b in zip(acc[k], acc['w=0 (words)'])]
    print(f'  paired {k} minus w=0: ' + ' '.join(f'{x:+.1f}' for x in diffs) + '  mean ' + ci(diffs))
cw = float(os.environ.get('WEIGHT', weights[0] if weights else 0))
conf = None
for s in seeds:
    c = point(runs[s], 'mixture-words-multinomial', cw)['counts']
    conf = c if conf is None else [[a + b for a, b in zip(x, y)] for x, y in zip(conf, c)]
print(f'  confusion of w={cw:g}, summed (rows truth):', cols, conf)
