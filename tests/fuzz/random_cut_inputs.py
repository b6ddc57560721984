#!/usr/bin/python3
"""Random inputs for fuzz_cut in its own format (tests/fuzz/fuzz_cut.cpp), for a long run of the
g++ replay driver where the libFuzzer build is not at hand:

    random_cut_inputs.py OUT_DIR COUNT [SEED]
    build/release/tests/fuzz/fuzz_replay_cut OUT_DIR

Each input: a random head byte (cutter, mesh, steps) and 1-12 records with the mode drawn
uniformly (random, face plane, through nodes, along an edge, fan) and random words.
"""
import os
import random
import sys


def main():
    out, count = sys.argv[1], int(sys.argv[2])
    rng = random.Random(int(sys.argv[3]) if len(sys.argv) > 3 else 1)
    os.makedirs(out, exist_ok=True)
    for i in range(count):
        data = bytes([rng.randrange(256)])
        for _ in range(rng.randint(1, 12)):
            data += bytes([rng.randrange(10)]) + bytes(rng.randrange(256) for _ in range(18))
        with open(os.path.join(out, f"r{i:06d}"), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
