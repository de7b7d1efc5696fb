#!/bin/bash
# usage: mot_topics_script_test.sh SCRIPT PROPRIO WORK_DIR: runs scripts/experiment-mot-topics in
# small (the environment sets TOPICS, PER, OBJECTS, WORDS) and checks its outputs: a row per T
# with the five methods' accuracies in [0, 1], and the plot.
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
svg = open(f"{sys.argv[1]}/fig7-9.svg").read()
assert svg.count("<polyline") == 5, svg
PY
