"""Bytes per scan on tofcompd's socket, JSON lines against compact frames (docs/performance.md,
"Compact frames"): subscribes to every beam in each format and averages the size of SCANS scans.
Usage: python3 bench/scan_bytes.py SOCKET"""
import json, socket, struct, sys
SCANS = 40
HEADER_BYTES = 128  # a compact frame's header (docs/protocol.md)
def bytes_per_scan(fmt):
    s = socket.socket(socket.AF_UNIX); s.connect(sys.argv[1]); f = s.makefile("rb")
    s.sendall(json.dumps({"op": "subscribe", "format": fmt}).encode() + b"\n")
    f.readline()  # the acknowledgement
    total = 0
    for _ in range(SCANS):
        if fmt == "json":
            total += len(f.readline())
        else:
            header = f.read(HEADER_BYTES)
            size = struct.unpack_from("<I", header, 8)[0]
            f.read(size - HEADER_BYTES)
            total += size
    return total / SCANS
for fmt in ("json", "compact"):
    print("%-7s %8.0f bytes per scan of 361 beams (mean of %d)" % (fmt, bytes_per_scan(fmt), SCANS))
