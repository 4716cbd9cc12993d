"""Writes a copy of a bench binary that valgrind 3.19 can run.

LLVM encodes `vmovq %xmmS,%xmmT` (S >= 8, T < 8) in its VEX D6 register form,
which valgrind 3.19 does not decode (it stops with SIGILL). In the stiff
method's stage solve the instruction only zero-extends a scalar for the add
after it, so every pair

    vmovq  %xmmS,%xmmT          c5 79 d6 /r
    vaddpd %xmmT,%xmmA,%xmmA    c5 .. 58 /r

becomes `vaddsd %xmmS,%xmmA,%xmmA` and a 3-byte nop: the same length and the
same number of instructions. The upper lane keeps A instead of A + 0.0 and T
is not written, so check that the copy prints the same step counts and
outputs as the original (docs/benchmarks.md does).

Usage: python3 benches/vmovq_patch.py BINARY COPY
"""

import os
import sys

data = bytearray(open(sys.argv[1], "rb").read())
count = 0
i = data.find(b"\xc5\x79\xd6")
while i >= 0:
    modrm, vex1, op2, modrm2 = data[i + 3], data[i + 5], data[i + 6], data[i + 7]
    src, dst = 8 + ((modrm >> 3) & 7), modrm & 7
    acc = (~vex1 >> 3) & 0xF  # vaddpd's first source (vvvv), also its destination
    if (
        modrm >> 6 == 3
        and data[i + 4] == 0xC5
        and op2 == 0x58
        and vex1 & 0x87 == 0x81  # VEX.R clear, 128-bit, 66 prefix
        and modrm2 >> 6 == 3
        and modrm2 & 7 == dst
        and (modrm2 >> 3) & 7 == acc
        and acc < 8
    ):
        vex2 = ((~acc & 0xF) << 3) | 3  # W0, vvvv = acc, L0, F2 prefix
        data[i : i + 8] = bytes(
            [0xC4, 0xC1, vex2, 0x58, 0xC0 | (acc << 3) | (src & 7), 0x0F, 0x1F, 0x00]
        )
        count += 1
    i = data.find(b"\xc5\x79\xd6", i + 1)
open(sys.argv[2], "wb").write(data)
# the copy runs like the original (valgrind needs the execute bit)
os.chmod(sys.argv[2], os.stat(sys.argv[1]).st_mode & 0o777)
print(f"{count} pairs rewritten")
