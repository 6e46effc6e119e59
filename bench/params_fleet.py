"""How long `axterm params apply` takes to bring several modules of one
slow bus to a parameter file, against the wire time of the transactions
it needed: a 100-setting file (user variables 0..99 of bank 2, every one
different from what the module holds, so each is read, written and read
back) applied with `--addresses 1-N` to a simulated TMCM-1110 bus served
with the wire time of BAUD (`axterm sim tmcm1110 --pty --baud BAUD
--address 1-N`), after a scan-free identify of each module.

    cargo build --release
    python3 bench/params_fleet.py target/release/axterm [MODULES] [BAUD]

Transactions counted from the run's JSON (per module: the identify, one
read of every setting of the file, each write and each read back), 9
bytes a request and 9 a reply (TMCL, §2), 10 bits a byte on the wire. The
ratio is the wall time of the whole `params apply` over that wire time:
1.0 would be a line never idle. Standard library only.
"""

import json
import os
import subprocess
import sys
import tempfile
import time

SETTINGS = 100
TMCL_EXCHANGE_BYTES = 9 + 9


def main():
    binary = sys.argv[1] if len(sys.argv) > 1 else "target/release/axterm"
    modules = int(sys.argv[2]) if len(sys.argv) > 2 else 8
    baud = int(sys.argv[3]) if len(sys.argv) > 3 else 9600
    addresses = f"1-{modules}" if modules > 1 else "1"
    sim = subprocess.Popen(
        [binary, "sim", "tmcm1110", "--pty", "--baud", str(baud), "--address", addresses],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    try:
        pty = sim.stdout.readline().strip()
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "fleet.toml")
            with open(path, "w") as f:
                f.write('family = "tmcl"\n[bank.2]\n')
                for n in range(SETTINGS):
                    f.write(f"{n} = {1000 + n}\n")
            start = time.monotonic()
            run = subprocess.run(
                [binary, "params", "apply", "--port", pty, "--baud", str(baud),
                 "--addresses", addresses, path, "--format", "json"],
                capture_output=True,
                text=True,
            )
            elapsed = time.monotonic() - start
    finally:
        sim.terminate()
        sim.wait()
    objects = [json.loads(line) for line in run.stdout.splitlines() if line.startswith("{")]
    per_module = [o for o in objects if "values" in o]
    transactions = 0
    for o in per_module:
        read_backs = sum(1 for v in o["values"] if v["outcome"] in ("verified", "differs"))
        transactions += 1 + SETTINGS + o["written"] + read_backs
    wire = transactions * TMCL_EXCHANGE_BYTES * 10 / baud
    print(f"exit code {run.returncode}; {len(per_module)} module(s) answered of {modules}")
    print(f"{transactions} transactions, {transactions * TMCL_EXCHANGE_BYTES} bytes, "
          f"wire time {wire:.2f} s at {baud} Bd")
    print(f"params apply took {elapsed:.2f} s: {elapsed / wire:.3f} x the wire time "
          f"(line busy {100 * wire / elapsed:.1f} %)")
    if run.returncode != 0:
        print(run.stderr, file=sys.stderr)


if __name__ == "__main__":
    main()
