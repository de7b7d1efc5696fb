#!/bin/bash
# usage: mot_topics_script_test.sh SCRIPT PROPRIO WORK_DIR: runs scripts/experiment-mot-topics in
# small (the environment sets TOPICS, PER, OBJECTS, WORDS, REPEATS=2) and checks its outputs: a
# row per T with the five methods' accuracies in [0, 1], the online curve the mean of the 50:50
# rule's two draws (seeds 1 and 2: different posteriors), and the plot.
set -euo pipefail
rm -rf "$3"
bash "$1" "$3" "$2" > "$3.txt"
cat "$3.txt"
python3 - "$3" <<'PY'
import json, sys
r = json.load(open(f"{sys.argv[1]}/fig7-9.json"))
assert [x["topics"] for x in r["rows"]] == [2, 5], r["rows"]
for x in r["rows"]:
    for m in ("argmax", "supervised", "mixture", "online", "unsupervised"):
        assert 0 <= x[m] <= 1, (m, x[m])
    runs = x["online_runs"]
    assert len(runs) == 2 and abs(x["online"] - sum(runs) / 2) < 1e-12, x
import filecmp
for t in (2, 5):
    d = f"{sys.argv[1]}/T{t}"
    assert not filecmp.cmp(f"{d}/online.csv", f"{d}/online-r2.csv", shallow=False), t
svg = open(f"{sys.argv[1]}/fig7-9.svg").read()
assert svg.count("<polyline") == 5, svg
PY
