#!/usr/bin/python3
"""A small fuzz seed from a real artifact payload: the RPI zonotope's generators cut to its first term.

The records (src/synthesis/record_file.cpp): name (u16 length + bytes), kind (u8: 1 matrix,
2 text, 3 integer), then for a matrix u32 rows, u32 cols and the doubles column by column,
for a text a u64 length and the bytes, for an integer 8 bytes. The case study's Z_G holds
97 % of a 4 MB payload; libFuzzer runs that at about 2 inputs a second. Its first `keep`
columns are still a zonotope (one term of the Minkowski sum), and the loader's checks ask
only for at least one generator, so the cut payload is an accepted artifact whose records
and checks the fuzzer reaches hundreds of times more often.

    shrink_artifact_seed.py PAYLOAD OUT [--keep 24]
"""
import argparse
import struct
import sys


def shrink(payload: bytes, keep: int) -> bytes:
    out = bytearray()
    i = 0
    found = False
    while i < len(payload):
        (name_len,) = struct.unpack_from("<H", payload, i)
        name = payload[i + 2:i + 2 + name_len].decode()
        kind = payload[i + 2 + name_len]
        head = i + 3 + name_len
        if kind == 1:
            rows, cols = struct.unpack_from("<II", payload, head)
            data = head + 8
            end = data + 8 * rows * cols
            if name == "Z_G" and cols > keep:
                found = True
                out += payload[i:head] + struct.pack("<II", rows, keep) + payload[data:data + 8 * rows * keep]
                i = end
                continue
        elif kind == 2:
            (length,) = struct.unpack_from("<Q", payload, head)
            end = head + 8 + length
        elif kind == 3:
            end = head + 8
        else:
            sys.exit(f"shrink_artifact_seed: record '{name}' at byte {i} has unknown kind {kind}")
        if end > len(payload):
            sys.exit(f"shrink_artifact_seed: record '{name}' at byte {i} runs past the payload's end")
        out += payload[i:end]
        i = end
    if not found:
        sys.exit(f"shrink_artifact_seed: no Z_G record with more than {keep} columns")
    return bytes(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("payload")
    ap.add_argument("out")
    ap.add_argument("--keep", type=int, default=24)
    args = ap.parse_args()
    with open(args.payload, "rb") as f:
        payload = f.read()
    small = shrink(payload, args.keep)
    with open(args.out, "wb") as f:
        f.write(small)
    print(f"shrink_artifact_seed: {len(payload)} -> {len(small)} bytes")


if __name__ == "__main__":
    main()
