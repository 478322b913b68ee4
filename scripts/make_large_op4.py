#!/usr/bin/env python3
"""Writes OUTPUT4 files with BIGMAT sparse matrices of huge declared size and few nonzeros,
shaped like pyyeti's Nastran-written nas_large_dim_bigmat_{binary,ascii}.op4 (issue 9, defect 5):
MATD (19 x 10,000,001), MATD22A (10^7 x 10^7), MATD21 (5 x 7, dense values 10 i + j).
Standard library only. Usage: make_large_op4.py OUT.op4 [--i64 | --ascii]
  default  little-endian binary, 4-byte words and markers, 8-byte names;
  --i64    as Nastran writes with 64-bit words: 8-byte words, 16-byte names holding 4 characters
           in each 8-byte word ("MATD    22A     "), plus MATDT (10,000,001 x 19);
  --ascii  ASCII, with the 16-character row/column counts and the "|I16" format suffix that
           Nastran writes when a count needs more than 8 characters, plus MATDT.
Layout (docs/formats-nastran-op4.md): Fortran records with length markers; header (cols, -rows,
form, type, name); per stored column (icol, irow=0, nw, strings of (L+1, row, L data words));
end record (cols+1, 1, 1 or 2 words, a dummy value)."""
import struct
import sys

BIG = 10_000_000


def matrices(with_transpose):
    out = [('MATD', 19, BIG + 1, {1: [(1, [1.0, 2.0])], 5_000_000: [(19, [3.5])],
                                  BIG + 1: [(7, [-4.25, 5.0, 6.0])]})]
    if with_transpose:
        out.append(('MATDT', BIG + 1, 19, {1: [(1, [1.0])], 2: [(1, [2.0])],
                                           19: [(5_000_000, [3.5])], 7: [(BIG + 1, [-4.25])],
                                           8: [(BIG + 1, [5.0])], 9: [(BIG + 1, [6.0])]}))
    out.append(('MATD22A', BIG, BIG, {1: [(1, [10.0])], 2_500_000: [(2_500_000, [20.0])],
                                      BIG: [(BIG - 1, [30.0, 40.0])]}))
    out.append(('MATD21', 5, 7, {j: [(1, [float(10 * i + j) for i in range(1, 6)])]
                                 for j in range(1, 8)}))
    return out


def binary(mats, wide):
    word = '<q' if wide else '<i'

    def ints(*v):
        return b''.join(struct.pack(word, x) for x in v)

    def record(payload):  # 4-byte Fortran markers in both layouts, as Nastran writes them
        return struct.pack('<i', len(payload)) + payload + struct.pack('<i', len(payload))

    blob = b''
    for name, rows, cols, columns in mats:
        # Real double: one 8-byte word per value with 64-bit words, two 4-byte words otherwise.
        per = 1 if wide else 2
        label = (name[:4].ljust(8) + name[4:8].ljust(8)) if wide else name.ljust(8)
        blob += record(ints(cols, -rows, 2, 2) + label.encode())
        for col in sorted(columns):
            data, nw = b'', 0
            for row, values in columns[col]:
                words = per * len(values)
                data += ints(words + 1, row) + struct.pack('<%dd' % len(values), *values)
                nw += 2 + words
            blob += record(ints(col, 0, nw) + data)
        blob += record(ints(cols + 1, 1, per) + struct.pack('<d', 0.0))
    return blob


def ascii_file(mats):
    fmt = '1P,3E23.16'
    lines = []
    for name, rows, cols, columns in mats:
        if max(cols, rows) >= 10_000_000:
            lines.append('%16d%16d%8d%8d%-8s%s|I16' % (cols, -rows, 2, 2, name, fmt))
        else:
            lines.append('%8d%8d%8d%8d%-8s%s' % (cols, -rows, 2, 2, name, fmt))
        for col in sorted(columns):
            nw = sum(2 + 2 * len(v) for _, v in columns[col])
            lines.append('%8d%8d%8d' % (col, 0, nw))
            for row, values in columns[col]:
                lines.append('%8d%8d' % (2 * len(values) + 1, row))
                for k in range(0, len(values), 3):
                    lines.append(''.join('%23.16E' % v for v in values[k:k + 3]))
        lines.append('%8d%8d%8d' % (cols + 1, 1, 1))
        lines.append('%23.16E' % 1.0)
    return ('\n'.join(lines) + '\n').encode()


def main(path, mode):
    if mode == '--ascii':
        blob = ascii_file(matrices(True))
    else:
        blob = binary(matrices(mode == '--i64'), mode == '--i64')
    with open(path, 'wb') as f:
        f.write(blob)


if __name__ == '__main__':
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else '')
