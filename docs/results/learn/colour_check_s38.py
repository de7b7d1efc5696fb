#!/usr/bin/python3
"""Session 38's check before colour words were made: do the objects' colours alone tell them
apart, on push frames (objects toppled, with clutter) against views of each object alone?

usage: colour_check_s38.py DIR [DILATE]
DIR holds `proprio sim record` episodes (320 x 240, 10 fps): for each catalogue object O,
tr-O-1..3 (`--scenario push --object O --clutter 3 --seed S`, the training views: every 3rd frame)
and te-O-11..15 (`--clutter 0 --seed S`, the test views: every 10th frame); each view is the
target's ground-truth mask grown by DILATE px (default 4). A view's document: 28 colour words
(12 hues x 2 saturations, 4 greys below saturation 0.25) of a 7 x 7 px box-blurred image at a
4-px grid inside the mask; each object's training counts pooled (+0.5), a test view classified by
the multinomial naive Bayes. Session 38: 300 of 300 test views right, at DILATE 4 and 12.
"""
import glob
import json
import os
import sys

import numpy as np
from PIL import Image, ImageFilter
from scipy import ndimage

STEP = 4


def words(rgb, mask):
    a = np.asarray(Image.fromarray(rgb).filter(ImageFilter.BoxBlur(3))).astype(np.float64) / 255
    ys, xs = np.nonzero(mask)
    sel = (ys % STEP == 0) & (xs % STEP == 0)
    px = a[ys[sel], xs[sel]]
    if len(px) < 10:
        return None
    mx, mn = px.max(1), px.min(1)
    d = mx - mn
    s = np.where(mx > 0, d / np.maximum(mx, 1e-9), 0)
    r, g, b = px.T
    h = np.zeros(len(px))
    nz = d > 1e-9
    i = nz & (mx == r)
    h[i] = ((g[i] - b[i]) / d[i]) % 6
    i = nz & (mx == g) & ~(mx == r)
    h[i] = (b[i] - r[i]) / d[i] + 2
    i = nz & (mx == b) & ~(mx == r) & ~(mx == g)
    h[i] = (r[i] - g[i]) / d[i] + 4
    hb = np.minimum((h / 6 * 12).astype(int), 11)
    sb = (s > 0.625).astype(int)  # the upper half of saturations 0.25..1
    vb = np.minimum((mx * 4).astype(int), 3)
    return np.bincount(np.where(s >= 0.25, hb * 2 + sb, 24 + vb), minlength=28).astype(float)


def views(ep, every, dilate):
    objs = json.load(open(f"{ep}/objects.json"))["objects"]
    tid = [o["id"] for o in objs if o["role"] == "target"][0]
    frames = sorted(os.listdir(f"{ep}/frames"))
    out = []
    for k in range(0, len(frames), every):
        m = np.array(Image.open(f"{ep}/masks/{frames[k]}")) == tid
        if dilate:
            m = ndimage.binary_dilation(m, iterations=dilate)
        w = words(np.array(Image.open(f"{ep}/frames/{frames[k]}").convert("RGB")), m)
        if w is not None:
            out.append(w)
    return out


def main(d, dilate):
    names = sorted({os.path.basename(p)[3:].rsplit("-", 1)[0] for p in glob.glob(d + "/tr-*")})
    pooled, test = [], []
    for n in names:
        pooled.append(sum(sum((views(e, 3, dilate) for e in glob.glob(f"{d}/tr-{n}-*")), [])) + 0.5)
        test.append(sum((views(e, 10, dilate) for e in glob.glob(f"{d}/te-{n}-*")), []))
    logp = np.log(np.array(pooled) / np.array(pooled).sum(1, keepdims=True))
    right = total = 0
    for c, n in enumerate(names):
        pred = np.array([int(np.argmax(logp @ w)) for w in test[c]])
        right += int((pred == c).sum())
        total += len(pred)
        print(f"{n:14s} {100 * (pred == c).mean():5.1f}% {np.bincount(pred, minlength=len(names))}")
    print(f"colour words alone, dilate {dilate}: {right} of {total} test views right")


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 4)
