"""The Python module tofcomp_client against a live tofcompd: the daemon on its emulated LMS 200
with a private socket and ring, read through the socket (JSON and compact) and the ring.
Run by ctest (tests/client/CMakeLists.txt sets PYTHONPATH and the binaries' paths)."""

import math
import os
import signal
import subprocess
import tempfile
import time
import unittest

import tofcomp_client

DEADLINE_S = 30.0  # generous: the machine is shared


def wait_for(condition, what):
    until = time.monotonic() + DEADLINE_S
    while time.monotonic() < until:
        value = condition()
        if value:
            return value
        time.sleep(0.02)
    raise AssertionError("%s: not within %.0f s" % (what, DEADLINE_S))


class LiveDaemon(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory(prefix="tofcomp-python-")
        root = os.environ["TOFCOMP_SOURCE_ROOT"]
        cls.socket = os.path.join(cls.dir.name, "tofcompd.sock")
        cls.ring = "/tofcomp-python-test-%d" % os.getpid()
        config = os.path.join(cls.dir.name, "tofcompd.yaml")
        with open(config, "w") as out:
            out.write("emulator:\n  enabled: true\n  scenario: %s/config/scenarios/default.yaml\n"
                      "case_sensor:\n  backend: simulated\n"
                      "calibration:\n  file: %s/config/calibration.yaml\n"
                      "outputs:\n  socket:\n    path: %s\n  shm:\n    name: %s\n"
                      % (root, root, cls.socket, cls.ring))
        cls.log = open(os.path.join(cls.dir.name, "tofcompd.log"), "w")
        cls.daemon = subprocess.Popen([os.environ["TOFCOMPD_BINARY"], "--config", config],
                                      stdout=cls.log, stderr=subprocess.STDOUT)
        def socket_or_exit():
            if cls.daemon.poll() is not None:
                with open(cls.log.name) as log:
                    raise AssertionError("tofcompd exited: " + log.read())
            return os.path.exists(cls.socket)
        wait_for(socket_or_exit, "the daemon's socket")

    @classmethod
    def tearDownClass(cls):
        cls.daemon.send_signal(signal.SIGTERM)
        cls.daemon.wait(timeout=DEADLINE_S)
        cls.log.close()
        cls.dir.cleanup()

    def test_hello_states_the_protocol_version(self):
        with tofcomp_client.Connection(self.socket, DEADLINE_S) as daemon:
            self.assertEqual(daemon.hello.protocol_major, 1)
            self.assertEqual(daemon.hello.protocol_minor, 0)
            self.assertRegex(daemon.hello.daemon_version, r"^\d+\.\d+\.\d+$")
        self.assertRegex(tofcomp_client.library_version(), r"^0\.\d+\.\d+$")

    def test_latest_of_a_range_and_a_refused_range(self):
        with tofcomp_client.Connection(self.socket, DEADLINE_S) as daemon:
            daemon.subscribe(beams=(0, 0))
            self.assertIsNotNone(daemon.next_scan(DEADLINE_S))  # a scan exists
            scan = daemon.latest(beams=(178, 182), timeout=DEADLINE_S)
            self.assertEqual([b.index for b in scan.beams], [178, 179, 180, 181, 182])
            self.assertEqual(scan.beam_count, 361)
            self.assertEqual(scan.resolution_deg, 0.5)
            with self.assertRaises(tofcomp_client.Error) as refused:
                daemon.latest(beams=(300, 400), timeout=DEADLINE_S)
            self.assertEqual(refused.exception.kind, "daemon")
            self.assertEqual(refused.exception.daemon_code, "bad_range")
            self.assertIn("361 beams", str(refused.exception))

    def test_compact_frames_carry_what_the_json_carries(self):
        with tofcomp_client.Connection(self.socket, DEADLINE_S) as as_json, \
                tofcomp_client.Connection(self.socket, DEADLINE_S) as as_compact:
            as_json.subscribe(beams=(170, 190), format="json")
            as_compact.subscribe(beams=(170, 190), format="compact")
            json_scans, compact_scans = {}, {}
            for _ in range(6):
                scan = as_json.next_scan(DEADLINE_S)
                json_scans[scan.sequence] = scan
                scan = as_compact.next_scan(DEADLINE_S)
                compact_scans[scan.sequence] = scan
            shared = sorted(set(json_scans) & set(compact_scans))
            self.assertGreaterEqual(len(shared), 3)
            for sequence in shared:
                j, c = json_scans[sequence], compact_scans[sequence]
                self.assertEqual(c.junction_c, j.junction_c)
                # The rays' timing (docs/protocol.md "Time"): a 0.5° scan of the emulated
                # LMS 200 interlaces two turns; both forms carry the same first ray.
                self.assertEqual(c.first_ray_ns, j.first_ray_ns)
                self.assertEqual(j.interlaced_turns, 2)
                self.assertLess(j.first_ray_ns, j.timestamp_ns)
                self.assertEqual(j.beam_time_ns(1) - j.beam_time_ns(0),
                                 round(j.turn_period_ns))
                self.assertEqual(len(c.beams), 21)
                for jb, cb in zip(j.beams, c.beams):
                    self.assertEqual(cb.index, jb.index)
                    self.assertEqual(cb.flags, jb.flags)
                    if math.isnan(jb.compensated_mm):
                        self.assertTrue(math.isnan(cb.compensated_mm))
                    else:  # float32 on the wire
                        self.assertAlmostEqual(cb.compensated_mm, jb.compensated_mm,
                                               delta=abs(jb.compensated_mm) * 2 ** -23)
                    self.assertTrue(math.isnan(cb.raw_mm))

    def test_the_ring_holds_the_scans_the_socket_sends(self):
        with tofcomp_client.Ring(self.ring) as ring, \
                tofcomp_client.Connection(self.socket, DEADLINE_S) as daemon:
            first = wait_for(ring.next, "a scan in the ring")
            self.assertEqual(len(first.beams), first.beam_count)
            daemon.subscribe(beams=(180, 180))
            sent = daemon.next_scan(DEADLINE_S)

            def ring_scan_of_sent():
                scan = ring.next()
                while scan is not None and scan.sequence < sent.sequence:
                    scan = ring.next()
                return scan
            same = wait_for(ring_scan_of_sent, "the sent scan in the ring")
            self.assertEqual(same.sequence, sent.sequence)
            self.assertEqual(same.first_ray_ns, sent.first_ray_ns)
            self.assertEqual(same.beams[180].raw_mm, sent.beams[0].raw_mm)
            self.assertEqual(same.beams[180].flags, sent.beams[0].flags)
            self.assertEqual(ring.latest().beam_count, 361)

    def test_any_request_and_its_reply(self):
        with tofcomp_client.Connection(self.socket, DEADLINE_S) as daemon:
            reply = daemon.call({"op": "stats"})
            self.assertTrue(reply["ok"])
            self.assertGreaterEqual(reply["socket"]["clients"], 1)


class WithoutDaemon(unittest.TestCase):
    def test_no_daemon_is_a_connect_error_naming_the_path(self):
        with self.assertRaises(tofcomp_client.Error) as failed:
            tofcomp_client.Connection("/nonexistent/tofcompd.sock", 1.0)
        self.assertEqual(failed.exception.kind, "connect")
        self.assertIn("/nonexistent/tofcompd.sock", str(failed.exception))

    def test_a_truncated_frame_is_refused(self):
        with self.assertRaises(tofcomp_client.Error) as failed:
            tofcomp_client.decode_compact(b"\x89TCS\x01\x00")
        self.assertEqual(failed.exception.kind, "bad_data")
        self.assertIn("fewer than the 128", str(failed.exception))


if __name__ == "__main__":
    unittest.main()
