#!/usr/bin/env python3
"""The floor in Python: N bare TMCL `GAP 1, 0` frames written and their
9-byte replies read with pyserial. Usage: pyserial_loop.py PORT [N] [BAUD]"""
import sys
import time

import serial

port, n = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 2000
baud = int(sys.argv[3]) if len(sys.argv) > 3 else 9600
frame = bytes([1, 6, 1, 0, 0, 0, 0, 0])
frame += bytes([sum(frame) & 0xFF])
with serial.Serial(port, baud, timeout=2) as s:
    start = time.perf_counter()
    for _ in range(n):
        s.write(frame)
        if len(s.read(9)) != 9:
            sys.exit("timeout")
    total = time.perf_counter() - start
print(f"pyserial: {n} frames in {total:.3f} s, {total / n * 1e6:.1f} µs each")
