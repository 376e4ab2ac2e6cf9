#!/usr/bin/env python3
"""Mean FLIP error from the reference implementation (PyPI flip-evaluator), for cross-checking
eval/metrics against it (tests/metrics/test_flip_crosscheck.cpp).

Usage: flip_crosscheck.py [--hdr] REF TEST [REF TEST ...]

Prints one line per pair: flip_evaluator's own mean (accumulated in float32 by its pooling code)
and the mean of its error map accumulated in float64, separated by a space. LDR (default): 8-bit sRGB PNGs, as flip_evaluator reads
them. --hdr: linear EXRs, HDR-FLIP with its defaults (ACES, automatic exposure range).
Run it with the repo's .venv (tools/python-env.sh makes it).
"""
import sys


def main(argv):
    args = argv[1:]
    mode = "LDR"
    if args and args[0] == "--hdr":
        mode = "HDR"
        args = args[1:]
    if not args or len(args) % 2:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        import flip_evaluator as flip
        import numpy as np
    except ImportError as e:
        print(f"flip_crosscheck: cannot import flip_evaluator ({e}); run tools/python-env.sh", file=sys.stderr)
        return 3
    for ref, test in zip(args[0::2], args[1::2]):
        error_map, mean, _ = flip.evaluate(ref, test, mode, applyMagma=False)
        print(f"{mean:.9f} {float(np.mean(error_map, dtype=np.float64)):.9f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
