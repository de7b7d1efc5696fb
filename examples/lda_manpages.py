#!/usr/bin/python3
"""Topics of 20 manual pages: scikit-learn's CountVectorizer, then proprio's online LDA, in one
Pipeline.

usage: PYTHONPATH=build/python /usr/bin/python3 examples/lda_manpages.py [--pages 20] [-k 4]

Reads the first PAGES English pages of section 1 under /usr/share/man (gzip'd troff), strips the
troff markup crudely, and prints each topic's most probable words and each page's main topic.
"""
import argparse
import gzip
import pathlib
import re

import numpy as np
from sklearn.feature_extraction.text import CountVectorizer
from sklearn.pipeline import Pipeline

from proprio.topics import LatentDirichletAllocation


def page_text(path):
    """The words of a troff page: requests, escapes and comments removed."""
    raw = gzip.open(path, "rt", errors="replace").read()
    lines = [re.sub(r"^\.\S+\s*", "", line) for line in raw.splitlines()
             if not line.startswith(('.\\"', "'\\\""))]
    text = " ".join(lines)
    return re.sub(r"\\(\(..|\[[^\]]*\]|f.|s[+-]?\d|.)", " ", text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--pages", type=int, default=20)
    ap.add_argument("-k", type=int, default=4, help="number of topics")
    ap.add_argument("--man-dir", default="/usr/share/man/man1")
    a = ap.parse_args()
    paths = sorted(p for p in pathlib.Path(a.man_dir).glob("*.gz") if p.stat().st_size > 2000)
    paths = paths[:a.pages]
    docs = [page_text(p) for p in paths]

    pipe = Pipeline([
        ("counts", CountVectorizer(stop_words="english", token_pattern=r"\b[a-z]{3,}\b",
                                   min_df=2, max_df=0.5)),
        ("lda", LatentDirichletAllocation(n_components=a.k, max_iter=20, batch_size=8,
                                          learning_offset=1.0, random_state=1)),
    ])
    theta = pipe.fit_transform(docs)  # pages x topics, rows sum to 1

    words = pipe.named_steps["counts"].get_feature_names_out()
    lda = pipe.named_steps["lda"]
    for k, row in enumerate(lda.components_):
        top = words[np.argsort(row)[::-1][:8]]
        print(f"topic {k}: {' '.join(top)}")
    for path, t in zip(paths, theta):
        print(f"  {path.name:28s} topic {t.argmax()} ({t.max():.2f})")
    print(f"perplexity (variational bound) of the {len(docs)} pages: "
          f"{lda.perplexity(pipe.named_steps['counts'].transform(docs)):.1f}")


if __name__ == "__main__":
    main()
