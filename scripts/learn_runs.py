#!/usr/bin/python3
"""Read a `proprio learn` run directory for the analysis scripts (issue 21, session 38).

A run directory holds learn.json (options, the executed and refused pushes with their ground
truth, the classes, the held-out figures, `ground_truth`) and decisions.jsonl (one event a line:
start, candidates, look, choose, push, region, views, ...). `proprio learn --out DIR` writes both;
scripts/experiment-learn writes DIR/MODE-sSEED and its wall time in DIR/MODE-sSEED.wall.

    run = learn_runs.load("OUT/D/quick-s51")
    run.json, run.truth, run.pushes, run.events      # learn.json, its ground_truth, its pushes, the log
    run.events_of("choose")                          # the log's events of one kind, in order
    run.turns()                                      # each turn's choices (see Turn, Choice)
    run.table()                                      # the objects and clutter on the table
    run.wall()                                       # DIR/MODE-sSEED.wall's seconds
    learn_runs.exists("OUT/D/quick-s51")             # has the directory a learn.json?

Used by scripts/repeat_trace.py, scripts/learn_paired.py, scripts/learn_untouched.py,
scripts/learn_seeds_table.py, scripts/learn_classes.py, scripts/learn_coverage.py,
scripts/learn_per_view.py and scripts/coverage_trace.py (its learn runs; it reads `proprio
selfsupervise` runs itself).
Standard library only; reads, never writes.
"""
import json
import os
from dataclasses import dataclass, field

_RAISE = object()  # Run.wall without `missing`: a missing RUN.wall raises


@dataclass
class Choice:
    """One choose event of a turn (7.2 a/d) and what the log held when it was made."""

    event: dict  # the choose event: object (the turn), blob, skipped [{blob, reason}], known, why
    candidates: dict  # the last candidates event before it (known: the classes' regions), or {}
    pushed: list  # (start, end) table points of every push executed before it, in order


@dataclass
class Turn:
    """A turn (a class: object index k = class object_{k+1}) as the log shows it."""

    index: int
    look: dict = None  # the turn's first look event with blob centres, or None
    choices: list = field(default_factory=list)  # its Choice-s, in order


class Run:
    """A learn run directory: learn.json (read at once) and decisions.jsonl (read when needed)."""

    def __init__(self, path):
        self.path = path
        with open(os.path.join(path, "learn.json")) as f:
            self.json = json.load(f)
        self._events = None

    @property
    def events(self):
        """decisions.jsonl's events, in order (read at the first use)."""
        if self._events is None:
            with open(os.path.join(self.path, "decisions.jsonl")) as f:
                self._events = [json.loads(x) for x in f if x.strip()]
        return self._events

    @property
    def truth(self):
        """learn.json's ground_truth (simulation: class_chosen, class_object, class_blobs, ...)."""
        return self.json["ground_truth"]

    @property
    def pushes(self):
        """learn.json's pushes: index, class, executed, located, views and the ground truth
        `intended` (the object under the planned push) and `moved` (the objects it moved)."""
        return self.json["pushes"]

    def events_of(self, name):
        """The log's events whose "event" is `name`, in order."""
        return [e for e in self.events if e["event"] == name]

    def class_indices(self):
        """Each class's turn index by its name: {"object_1": 0, ...}, one a turn."""
        return {f"object_{i + 1}": i for i in range(len(self.truth["class_chosen"]))}

    def table(self):
        """The names of the objects and clutter on the table (learn.json options)."""
        options = self.json["options"]
        return {n.strip() for key in ("objects", "clutter")
                for n in options.get(key, "").split(",") if n.strip()}

    def first_look_centres(self):
        """The blob centres (table, m) of the run's first look, or None."""
        for e in self.events:
            if e["event"] == "look" and "centres" in e:
                return e["centres"]
        return None

    def turns(self):
        """Each turn that chose at least once, by index: its first look with centres and its
        choices, each with the last candidates event before it and the pushes executed before it
        (decisions.jsonl's push events with executed true: plan start and end)."""
        turns, candidates, pushed = {}, None, []
        for e in self.events:
            kind = e["event"]
            if kind == "candidates":
                candidates = e
            elif kind == "look" and "centres" in e:
                turn = turns.setdefault(e["object"], Turn(e["object"]))
                if turn.look is None:
                    turn.look = e
            elif kind == "choose":
                turn = turns.setdefault(e["object"], Turn(e["object"]))
                turn.choices.append(Choice(e, candidates or {}, list(pushed)))
            elif kind == "push" and e.get("executed"):
                pushed.append((e["plan"]["start"], e["plan"]["end"]))
        return {k: t for k, t in turns.items() if t.choices}

    def wall(self, missing=_RAISE):
        """The run's wall seconds (RUN.wall beside the directory); without it `missing`, or
        FileNotFoundError when `missing` is not given."""
        path = f"{self.path.rstrip('/')}.wall"
        if missing is not _RAISE and not os.path.exists(path):
            return missing
        with open(path) as f:
            return float(f.read())


def load(path):
    """The learn run in directory `path`."""
    return Run(path)


def exists(path):
    """Whether directory `path` holds a learn.json: a run, finished or not (an unfinished one has
    learn.json "complete" false or an INCOMPLETE file in the directory)."""
    return os.path.exists(os.path.join(path, "learn.json"))
