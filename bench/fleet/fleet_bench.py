#!/usr/bin/env python3
"""A fleet on one machine: N tofcompd on emulated LMS 200s, each with its tofcomp-mqtt-bridge,
all publishing to one local mosquitto; one subscriber takes everything (tofcomp/bench/#).

For each N (default 1, 10, 50) it measures over a window after a warm-up:
  - messages per second received by the subscriber (and per topic kind);
  - end-to-end latency of the junction topic, p50 and p99: the subscriber's receive time less the
    scan's timestamp_ns (when tofcompd read the scan's last byte), so it spans tofcompd's
    compensation and publication, the socket, the bridge, the broker and the subscriber; and the
    bridge-to-subscriber part alone (receive time less published_ns);
  - CPU of the daemons, the bridges and the broker, in % of one core, from /proc/PID/stat
    (utime + stime) at the window's start and end.

Usage: python3 bench/fleet/fleet_bench.py [--build build] [--counts 1,10,50] [--seconds 30]
Needs mosquitto and mosquitto-clients (tools/setup.sh); TOFCOMPD and TOFCOMP name another build's
programs. Writes the table to stdout and the
figures as JSON to --json (default: fleet_bench.json in the working directory).
"""
import argparse
import json
import os
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time

TICKS = os.sysconf("SC_CLK_TCK")
WARM_UP_S = 5.0
START_DEADLINE_S = 120.0


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def cpu_seconds(pid):
    """utime + stime of a process, in seconds (fields 14 and 15 of /proc/PID/stat)."""
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS


def percentile(values, q):
    if not values:
        return float("nan")
    ordered = sorted(values)
    index = min(len(ordered) - 1, max(0, round(q / 100 * (len(ordered) - 1))))
    return ordered[index]


def wait_until(what, check, deadline_s=START_DEADLINE_S):
    until = time.monotonic() + deadline_s
    while time.monotonic() < until:
        if check():
            return
        time.sleep(0.2)
    raise RuntimeError(f"no {what} within {deadline_s} s")


class Fleet:
    def __init__(self, build, work, port, count, tag):
        self.build, self.work, self.port, self.count, self.tag = build, work, port, count, tag
        self.tofcomp = os.environ.get("TOFCOMP", os.path.join(build, "cli/tofcomp"))
        self.tofcompd = os.environ.get("TOFCOMPD", os.path.join(build, "daemon/tofcompd"))
        self.daemons, self.bridges = [], []

    def sock(self, i):
        return os.path.join(self.work, f"s{i}.sock")

    def publishing(self, i):
        result = subprocess.run(
            [self.tofcomp, "query", "--socket", self.sock(i),
             "--timeout", "1", "status"], capture_output=True, text=True)
        return "status.state: publishing" in result.stdout

    def start(self):
        config = os.path.join(self.work, "tofcompd.yaml")
        # The built-in default, its data files named absolutely (its paths are relative to it).
        data = os.path.join(os.path.dirname(self.tofcompd), "../share/tofcomp")
        text = subprocess.run([self.tofcompd,
                               "--print-default-config"], capture_output=True, text=True,
                              check=True).stdout
        text = text.replace("scenario: scenarios/", f"scenario: {data}/scenarios/")
        text = text.replace("file: calibration.yaml", f"file: {data}/calibration.yaml")
        with open(config, "w") as f:
            f.write(text)
        for i in range(self.count):
            log = open(os.path.join(self.work, f"d{i}.log"), "w")
            self.daemons.append(subprocess.Popen(
                [self.tofcompd, "--config", config,
                 "--socket", self.sock(i), "--shm", f"/{self.tag}-{i}"],
                stdout=log, stderr=subprocess.STDOUT))
        for i in range(self.count):
            wait_until(f"scans from tofcompd {i}", lambda i=i: self.publishing(i))
        for i in range(self.count):
            path = os.path.join(self.work, f"b{i}.yaml")
            with open(path, "w") as f:
                f.write(f"broker: {{host: 127.0.0.1, port: {self.port}}}\n"
                        f"site: bench\ninstance: s{i}\n"
                        f"tofcompd: {{socket: {self.sock(i)}}}\n"
                        "publish: {junction_ms: 0}\n")
            log = open(os.path.join(self.work, f"b{i}.log"), "w")
            self.bridges.append(subprocess.Popen(
                [os.path.join(self.build, "bridges/mqtt/tofcomp-mqtt-bridge"), "--config", path],
                stdout=log, stderr=subprocess.STDOUT))

    def stop(self):
        for p in self.bridges + self.daemons:
            p.send_signal(signal.SIGTERM)
        for p in self.bridges + self.daemons:
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        for i in range(self.count):
            try:
                os.unlink(f"/dev/shm/{self.tag}-{i}")
            except FileNotFoundError:
                pass


def run(build, count, seconds, work):
    port = free_port()
    conf = os.path.join(work, "mosquitto.conf")
    with open(conf, "w") as f:
        f.write(f"listener {port} 127.0.0.1\nallow_anonymous true\npersistence false\n"
                "log_dest none\n")
    broker = subprocess.Popen(["mosquitto", "-c", conf], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    fleet = Fleet(build, work, port, count, f"fleet-{os.getpid()}-{count}")
    received = os.path.join(work, f"received-{count}.txt")
    subscriber = None
    try:
        wait_until("the broker", lambda: subprocess.run(
            ["mosquitto_pub", "-h", "127.0.0.1", "-p", str(port), "-t", "probe", "-m", "x"],
            capture_output=True).returncode == 0)
        fleet.start()
        out = open(received, "w")
        subscriber = subprocess.Popen(
            ["mosquitto_sub", "-h", "127.0.0.1", "-p", str(port), "-t", "tofcomp/bench/#",
             "-F", "%U %t %p"], stdout=out, stderr=subprocess.DEVNULL)
        time.sleep(WARM_UP_S)  # every bridge connected and streaming (a benchmark, not a test)
        pids = {"daemons": [p.pid for p in fleet.daemons],
                "bridges": [p.pid for p in fleet.bridges], "broker": [broker.pid]}
        before = {k: sum(cpu_seconds(p) for p in v) for k, v in pids.items()}
        t0 = time.time()
        time.sleep(seconds)
        t1 = time.time()
        after = {k: sum(cpu_seconds(p) for p in v) for k, v in pids.items()}
    finally:
        if subscriber:
            subscriber.terminate()
            subscriber.wait()
        fleet.stop()
        broker.terminate()
        broker.wait()

    kinds, latency_ms, hop_ms = {}, [], []
    with open(received) as f:
        for line in f:
            parts = line.rstrip("\n").split(" ", 2)
            if len(parts) < 3:
                continue
            at = float(parts[0])
            if not t0 <= at < t1:
                continue
            kind = parts[1].rsplit("/", 1)[-1]
            kinds[kind] = kinds.get(kind, 0) + 1
            if kind == "junction":
                payload = json.loads(parts[2])
                # %U has nanoseconds; float seconds keep ~0.2 us at today's epoch.
                latency_ms.append((at - payload["timestamp_ns"] / 1e9) * 1e3)
                hop_ms.append((at - payload["published_ns"] / 1e9) * 1e3)
    window = t1 - t0
    cpu = {k: 100.0 * (after[k] - before[k]) / window for k in before}
    return {
        "scanners": count, "window_s": round(window, 2),
        "messages_per_s": round(sum(kinds.values()) / window, 1),
        "per_kind_per_s": {k: round(v / window, 2) for k, v in sorted(kinds.items())},
        "junction_samples": len(latency_ms),
        "latency_ms": {"p50": round(percentile(latency_ms, 50), 2),
                       "p99": round(percentile(latency_ms, 99), 2),
                       "max": round(max(latency_ms), 2) if latency_ms else None},
        "bridge_to_subscriber_ms": {"p50": round(percentile(hop_ms, 50), 2),
                                    "p99": round(percentile(hop_ms, 99), 2)},
        "cpu_percent_of_one_core": {k: round(v, 1) for k, v in cpu.items()},
        "cpu_percent_per_scanner": {k: round(cpu[k] / count, 2) for k in ("daemons", "bridges")},
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--counts", default="1,10,50")
    parser.add_argument("--seconds", type=float, default=30.0)
    parser.add_argument("--json", default="fleet_bench.json")
    args = parser.parse_args()
    for tool in ("mosquitto", "mosquitto_sub", "mosquitto_pub"):
        if not shutil.which(tool):
            sys.exit(f"fleet_bench: {tool} not found (tools/setup.sh installs it)")
    results = []
    for count in (int(c) for c in args.counts.split(",")):
        with tempfile.TemporaryDirectory(prefix="fleet-bench-") as work:
            print(f"N = {count}: starting {count} tofcompd and bridges ...", file=sys.stderr)
            results.append(run(os.path.abspath(args.build), count, args.seconds, work))
            print(json.dumps(results[-1]), file=sys.stderr)
    print(f"{'N':>4} {'msg/s':>8} {'junction p50 ms':>16} {'p99 ms':>8} {'hop p50':>8} "
          f"{'hop p99':>8} {'daemons %':>10} {'bridges %':>10} {'broker %':>9}")
    for r in results:
        c = r["cpu_percent_of_one_core"]
        print(f"{r['scanners']:>4} {r['messages_per_s']:>8} {r['latency_ms']['p50']:>16} "
              f"{r['latency_ms']['p99']:>8} {r['bridge_to_subscriber_ms']['p50']:>8} "
              f"{r['bridge_to_subscriber_ms']['p99']:>8} {c['daemons']:>10} {c['bridges']:>10} "
              f"{c['broker']:>9}")
    with open(args.json, "w") as f:
        json.dump({"machine": {"cpus": os.cpu_count(), "uname": " ".join(os.uname())},
                   "seconds": args.seconds, "results": results}, f, indent=1)


if __name__ == "__main__":
    main()
