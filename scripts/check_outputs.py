#!/usr/bin/python3
"""Checks that every file a sphib run left under a final name opens and is whole.

  /usr/bin/python3 scripts/check_outputs.py DIR [--complete]

HDF5 files (output.h5, checkpoint.h5) open with h5py and every dataset in them reads; the
checkpoint has its fluid state and run record, and its seal holds (the SHA-256 of its bytes after
the first 512); summary.json parses; every CSV row has the header's
number of fields, each a number; the XDMF files parse as XML and name datasets output.h5 holds.
.part files (incomplete by name) and the lock file of a killed run are skipped. With --complete the
directory must hold a finished run: summary.json, output.h5, diagnostics.csv and no .part file.
Prints one line per file; exits 1 if any file is broken (or, with --complete, missing).
"""
import csv
import hashlib
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

import h5py


def check_h5(path):
    with h5py.File(path, "r") as f:
        datasets = []
        f.visititems(lambda name, obj: datasets.append(name) if isinstance(obj, h5py.Dataset) else None)
        for name in datasets:
            f[name][()]
        if os.path.basename(path) == "checkpoint.h5":
            for need in ("fluid", "scene", "run/series"):
                if need not in f:
                    raise ValueError(f"no {need}")
            if f.attrs["checkpoint_format"] != "3":
                raise ValueError("checkpoint_format is not 3")
    if os.path.basename(path) == "checkpoint.h5":  # the seal: the SHA-256 of every byte after the first 512
        with open(path, "rb") as fh:
            data = fh.read()
        head = data[:512].split(b"\n")
        if head[0] != b"sphib checkpoint 3" or head[1] != b"sha256 " + hashlib.sha256(data[512:]).hexdigest().encode():
            raise ValueError("its seal does not hold")
    return f"{len(datasets)} datasets"


def check_csv(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    if not rows:
        raise ValueError("empty")
    for k, row in enumerate(rows[1:], start=2):
        if len(row) != len(rows[0]):
            raise ValueError(f"line {k} has {len(row)} fields for {len(rows[0])} columns")
        for cell in row:
            float(cell)  # nan and inf parse too
    return f"{len(rows) - 1} rows"


def check_json(path):
    with open(path) as fh:
        j = json.load(fh)
    for key in ("stop_reason", "steps", "time", "run_id"):
        if key not in j:
            raise ValueError(f"no {key}")
    if not (isinstance(j["time"], (int, float)) and math.isfinite(j["time"])):
        raise ValueError("time is not a number")
    return f"stop_reason {j['stop_reason']}, step {j['steps']}"


def check_xdmf(path, directory):
    root = ET.parse(path).getroot()
    items = [e.text.strip() for e in root.iter("DataItem")]
    h5 = None
    for item in items:
        name, where = item.split(":", 1)
        if h5 is None:
            h5 = h5py.File(os.path.join(directory, name), "r")
        if where not in h5:
            raise ValueError(f"{item} is not in {name}")
    return f"{len(items)} data items"


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 1:
        sys.exit(__doc__)
    directory, complete = args[0], "--complete" in sys.argv
    bad = 0
    names = sorted(os.listdir(directory))
    for name in names:
        path = os.path.join(directory, name)
        if name.endswith(".part") or name == ".sphib.lock":
            continue
        try:
            if name.endswith(".h5"):
                what = check_h5(path)
            elif name.endswith(".csv"):
                what = check_csv(path)
            elif name.endswith(".json"):
                what = check_json(path)
            elif name.endswith(".xdmf"):
                what = check_xdmf(path, directory)
            else:
                raise ValueError("not a file sphib writes")
            print(f"  ok  {path}: {what}")
        except Exception as e:  # noqa: BLE001 - every failure is a broken file
            bad += 1
            print(f"  BAD {path}: {type(e).__name__}: {e}")
    if complete:
        for need in ("summary.json", "output.h5", "diagnostics.csv", "checkpoint.h5"):
            if need not in names:
                bad += 1
                print(f"  BAD {directory}: no {need} (the run should have finished)")
        for name in names:
            if name.endswith(".part") or name == ".sphib.lock":
                bad += 1
                print(f"  BAD {directory}: {name} left by a finished run")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
