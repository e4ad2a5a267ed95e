#!/usr/bin/env python3
"""Writes a particles CSV (x, y, z, r) of equal spheres on a jittered simple cubic lattice.

A small, loose, reproducible starting packing for example scenes and tests of the engine,
before ballistic deposition exists. Units: R = 1.
Example: tools/make_lattice_particles.py --per-side 6 --layers 6 --spacing 2.5 > out.csv
"""
import argparse
import random
import sys


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--per-side", type=int, default=6, help="spheres along x and y")
    parser.add_argument("--layers", type=int, default=6, help="layers along z")
    parser.add_argument("--spacing", type=float, default=2.5, help="lattice spacing [R] (> 2)")
    parser.add_argument("--jitter", type=float, default=0.2, help="max displacement [R]")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    if args.spacing - 2 * args.jitter < 2.0:
        parser.error("spacing - 2*jitter must be >= 2 so that no spheres overlap")
    rng = random.Random(args.seed)
    out = sys.stdout
    out.write(f"# jittered lattice: per_side={args.per_side} layers={args.layers} "
              f"spacing={args.spacing} jitter={args.jitter} seed={args.seed}; "
              f"box lx = ly = {args.per_side * args.spacing}\n")
    out.write("x,y,z,r\n")
    for k in range(args.layers):
        for j in range(args.per_side):
            for i in range(args.per_side):
                def jit() -> float:
                    return rng.uniform(-args.jitter, args.jitter)
                x = (i + 0.5) * args.spacing + jit()
                y = (j + 0.5) * args.spacing + jit()
                z = 1.0 + k * args.spacing + abs(jit())
                out.write(f"{x:.6f},{y:.6f},{z:.6f},1\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
