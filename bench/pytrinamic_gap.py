#!/usr/bin/env python3
"""N `get_axis_parameter(1, 0)` calls through PyTrinamic's serial TMCL
interface. Usage: pytrinamic_gap.py PORT [N] [BAUD]"""
import sys
import time

from pytrinamic.connections import SerialTmclInterface

port, n = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 2000
baud = int(sys.argv[3]) if len(sys.argv) > 3 else 9600
interface = SerialTmclInterface(port, datarate=baud)
start = time.perf_counter()
for _ in range(n):
    interface.get_axis_parameter(1, 0)
total = time.perf_counter() - start
interface.close()
print(f"pytrinamic: {n} get_axis_parameter in {total:.3f} s, {total / n * 1e6:.1f} µs each")
