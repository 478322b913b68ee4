#!/usr/bin/env python3
"""Writes a binary little-endian OUTPUT4 file with BIGMAT sparse matrices of huge declared size
and few nonzeros, shaped like pyyeti's Nastran-written nas_large_dim_bigmat_binary.op4 (issue 9,
defect 5): MATD (19 x 10,000,001), MATD22A (10^7 x 10^7), MATD21 (5 x 7, dense values).
Standard library only. Usage: make_large_op4.py OUT.op4
Layout (docs/formats-nastran-op4.md): Fortran records with 4-byte length markers; header
(cols, -rows, form, type, name); per stored column (icol, irow=0, nw, strings of (L+1, row,
L data words)); end record (cols+1, 1, 2 words, a dummy double)."""
import struct
import sys


def record(payload: bytes) -> bytes:
    return struct.pack('<i', len(payload)) + payload + struct.pack('<i', len(payload))


def matrix(name, rows, cols, columns):
    """columns: {col (1-based): [(row (1-based), [values...]), ...]} strings of consecutive rows."""
    out = record(struct.pack('<4i', cols, -rows, 2, 2) + name.ljust(8).encode())  # form 2, real double
    for col in sorted(columns):
        data = b''
        nw = 0
        for row, values in columns[col]:
            words = 2 * len(values)  # a double is 2 words of 4 bytes
            data += struct.pack('<2i', words + 1, row) + struct.pack('<%dd' % len(values), *values)
            nw += 2 + words
        out += record(struct.pack('<3i', col, 0, nw) + data)
    out += record(struct.pack('<3i', cols + 1, 1, 2) + struct.pack('<d', 0.0))
    return out


def main(path):
    big = 10_000_000
    blob = matrix('MATD', 19, big + 1, {1: [(1, [1.0, 2.0])], 5_000_000: [(19, [3.5])],
                                         big + 1: [(7, [-4.25, 5.0, 6.0])]})
    blob += matrix('MATD22A', big, big, {1: [(1, [10.0])], 2_500_000: [(2_500_000, [20.0])],
                                         big: [(big - 1, [30.0, 40.0])]})
    blob += matrix('MATD21', 5, 7, {j: [(1, [float(10 * i + j) for i in range(1, 6)])]
                                    for j in range(1, 8)})
    with open(path, 'wb') as f:
        f.write(blob)


if __name__ == '__main__':
    main(sys.argv[1])
