#!/usr/bin/env bash
# tofcomp-mqtt-bridge against a real mosquitto on loopback (free ports, a temporary directory):
# one plain listener, and one TLS listener with a CA and a server certificate made here by openssl
# and a password file made by mosquitto_passwd. A real tofcompd on its emulated LMS 200. Shown:
# bad configurations refused naming the key; the retained online state; status and junction
# payloads as `tofcomp query` of the same daemon says; the will ("offline") after kill -9;
# commands refused when not allowed (and malformed ones), reload executed when allowed; "offline"
# on SIGTERM; the broker and tofcompd going away and coming back; TLS with credentials accepted,
# a wrong password and an unknown CA refused with a clear error; a world-readable password file
# refused.
set -euo pipefail
build=$(cd "$1" && pwd)
bridge="$build/bridges/mqtt/tofcomp-mqtt-bridge"
# TOFCOMPD, TOFCOMP: the programs of another build of this tree (while this one lacks them).
tofcompd="${TOFCOMPD:-$build/daemon/tofcompd}"
tofcomp="${TOFCOMP:-$build/cli/tofcomp}"
work=$(mktemp -d)
tag="mqtt-test-$$"
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -9 "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  rm -f "/dev/shm/$tag"*
  rm -rf "$work"
}
trap cleanup EXIT
deadline_s=60
fail() { echo "FAIL: $*"; for log in "$work"/*.log; do echo "--- $log"; tail -n 30 "$log"; done; exit 1; }

# Waits until the command succeeds, or fails after the deadline naming what was awaited.
wait_for() {
  local what=$1; shift
  for _ in $(seq $((deadline_s * 10))); do
    if "$@" > /dev/null 2>&1; then return 0; fi
    sleep 0.1
  done
  fail "no $what within ${deadline_s} s"
}

free_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
plain=$(free_port)
tls=$(free_port)
base=tofcomp/testsite/left

# --- the broker: a CA, a server certificate for 127.0.0.1, a password file ---------------------
cd "$work"
openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=tofcomp-test-ca \
  -keyout ca.key -out ca.crt 2> /dev/null
openssl req -newkey rsa:2048 -nodes -subj /CN=127.0.0.1 -keyout server.key -out server.csr 2> /dev/null
openssl x509 -req -in server.csr -CA ca.crt -CAkey ca.key -CAcreateserial -days 1 \
  -extfile <(printf 'subjectAltName=IP:127.0.0.1,DNS:localhost') -out server.crt 2> /dev/null
openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=another-ca \
  -keyout other.key -out other.crt 2> /dev/null
mosquitto_passwd -c -b passwd fleet 'correct horse' 2> /dev/null
chmod 644 ca.crt server.crt server.key passwd
cat > mosquitto.conf <<EOF
per_listener_settings true
persistence false
log_dest stderr
listener $plain 127.0.0.1
allow_anonymous true
listener $tls 127.0.0.1
allow_anonymous false
password_file $work/passwd
cafile $work/ca.crt
certfile $work/server.crt
keyfile $work/server.key
EOF
# Started as root, mosquitto drops to its own user; the files above are readable by it.
chmod 755 "$work"
start_broker() {
  mosquitto -c "$work/mosquitto.conf" >> "$work/mosquitto.log" 2>&1 &
  broker_pid=$!
  pids+=("$broker_pid")
  wait_for "broker on port $plain" mosquitto_pub -h 127.0.0.1 -p "$plain" -t probe -m up
}
start_broker
sub() { mosquitto_sub -h 127.0.0.1 -p "$plain" "$@"; }
pub() { mosquitto_pub -h 127.0.0.1 -p "$plain" "$@"; }

# --- tofcompd on its emulated LMS 200, with a configuration file a reload can re-read ----------
# The built-in default with its data files named absolutely (its paths are relative to the file).
data="$(dirname "$tofcompd")/../share/tofcomp"
"$tofcompd" --print-default-config |
  sed -e "s|scenario: scenarios/|scenario: $data/scenarios/|" \
      -e "s|file: calibration.yaml|file: $data/calibration.yaml|" > tofcompd.yaml
start_tofcompd() {
  "$tofcompd" --config tofcompd.yaml --socket "$work/tofcompd.sock" --shm "/$tag" \
    >> "$work/tofcompd.log" 2>&1 &
  tofcompd_pid=$!
  pids+=("$tofcompd_pid")
  wait_for "scans from tofcompd" sh -c \
    "'$tofcomp' query --socket '$work/tofcompd.sock' --timeout 1 status | grep -q '^status.state: publishing'"
}
start_tofcompd

# --- configurations ---------------------------------------------------------------------------
write_config() {  # NAME, then extra YAML lines
  local name=$1; shift
  {
    echo "broker:"
    echo "  host: 127.0.0.1"
    echo "  port: $plain"
    echo "site: testsite"
    echo "instance: left"
    echo "tofcompd:"
    echo "  socket: $work/tofcompd.sock"
    echo "reconnect: {initial_s: 1, max_s: 2}"
    echo "publish: {status_ms: 500, junction_ms: 0, diagnosis_ms: 1000, ranges_ms: 1000, ranges_beam_step: 4}"
    for line in "$@"; do echo "$line"; done
  } > "$work/$name.yaml"
}
refused_config() {  # NAME, EXPECTED-TEXT
  if "$bridge" --config "$work/$1.yaml" --check-config > "$work/$1.out" 2>&1; then
    fail "$1: a bad configuration was accepted"
  fi
  grep -qF -- "$2" "$work/$1.out" || { cat "$work/$1.out"; fail "$1: no '$2' in the error"; }
}
write_config good
"$bridge" --config good.yaml --check-config | grep -qF "good.yaml: valid; broker 127.0.0.1:$plain as tofcomp-testsite-left" ||
  fail "--check-config did not pass"
write_config typo "comands: {reload: true}"
refused_config typo "comands"
sed "s/port: $plain/port: 70000/" good.yaml > port.yaml
refused_config port "broker.port must be between 1 and 65535, not 70000"
sed "s/site: testsite/site: 'plant+a'/" good.yaml > site.yaml
refused_config site "site is no topic name"
write_config reload-text "commands: {reload: yes please}"
refused_config reload-text "commands.reload must be true or false"
echo "bad configurations are refused naming the key"

# --- the bridge with commands off -------------------------------------------------------------
start_bridge() {  # CONFIG LOG
  "$bridge" --config "$work/$1.yaml" >> "$work/$2.log" 2>&1 &
  bridge_pid=$!
  pids+=("$bridge_pid")
}
retained() { sub -t "$1" -C 1 -W 5 2> /dev/null; }
online_is() { [ "$(retained "$base/online")" = "$1" ]; }
start_bridge good bridge
wait_for "the bridge's connection" grep -q 'connected to the broker' "$work/bridge.log"
# Subscribed after the bridge published it: the broker kept it (retained).
wait_for "the retained online state" online_is online
echo "online is retained"

# Status: the daemon's status as `tofcomp query status` gives it.
wait_for "a status with tofcompd's answer" sh -c "mosquitto_sub -h 127.0.0.1 -p $plain -t $base/status -C 1 -W 5 | grep -q '\"state\"'"
retained "$base/status" > status.json
"$tofcomp" query --socket "$work/tofcompd.sock" status --json > query-status.json
python3 - status.json query-status.json <<'EOF' || fail "status payload differs from tofcomp query status"
import json, sys
mqtt = json.load(open(sys.argv[1]))["tofcompd"]
query = json.load(open(sys.argv[2]))["status"]
for key in ("config", "device", "state", "link", "power", "calibration", "case_sensor", "recording"):
    assert mqtt[key] == query[key], (key, mqtt[key], query[key])
assert mqtt["latest"]["beams"] == query["latest"]["beams"] == 361
assert mqtt["latest"]["sequence"] <= query["latest"]["sequence"]
print("status agrees:", mqtt["state"], "| calibration", mqtt["calibration"]["id"])
EOF
retained "$base/calibration" | grep -q '"id":1' || fail "no retained calibration 1"

# Junction: per scan (junction_ms 0), against the same scans subscribed through the socket.
mosquitto_sub -h 127.0.0.1 -p "$plain" -t "$base/junction" -C 30 -W 30 > junction.txt &
junction_sub=$!
"$tofcomp" query --socket "$work/tofcompd.sock" subscribe -n 60 --beams 0:0 --json > scans.txt
wait "$junction_sub" || fail "fewer than 30 junction messages in 30 s"
python3 - junction.txt scans.txt <<'EOF' || fail "junction payloads differ from the daemon's scans"
import json, sys
mqtt = {m["sequence"]: m for m in map(json.loads, open(sys.argv[1]))}
scans = {s["sequence"]: s for s in map(json.loads, open(sys.argv[2]))}
common = sorted(set(mqtt) & set(scans))
assert len(common) >= 10, f"only {len(common)} sequences in both"
for seq in common:
    m, s = mqtt[seq], scans[seq]
    for key in ("junction_c", "junction_std_c", "case_c", "timestamp_ns", "calibration_id"):
        assert m[key] == s[key], (seq, key, m[key], s[key])
    assert m["published_ns"] >= m["timestamp_ns"]
print(f"junction agrees on {len(common)} scans")
EOF

# Ranges and diagnosis: bounded summaries of the period.
sub -t "$base/ranges" -C 1 -W 10 > ranges.json || fail "no ranges summary"
python3 - ranges.json <<'EOF' || fail "ranges summary malformed"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["beam_step"] == 4 and len(r["mean_mm"]) == 91 == len(r["std_mm"]) == len(r["valid_share"]), r.keys()
assert r["scans"] >= 2, r["scans"]  # 37.5 a second on an idle machine; fewer on a loaded one
assert r["to_ns"] > r["from_ns"] and all(0 <= v <= 1 for v in r["valid_share"])
wall = r["mean_mm"][45]  # beam 180, straight ahead: the default scenario's wall at 3000 mm
assert abs(wall - 3000) < 20, wall
assert set(r["flag_share"]) >= {"no_echo", "temperature_extrapolated"}
print(f"ranges: {r['scans']} scans, beam 180 mean {wall} mm")
EOF
retained "$base/diagnosis" | python3 -c 'import json,sys; d=json.load(sys.stdin); assert "findings" in d and "flag_share" in d' ||
  fail "no retained diagnosis"

# Commands: a subscriber on the reply topic, known to be subscribed once it saw a probe.
ask() {  # PAYLOAD; prints the reply
  local out="$work/reply.$RANDOM"
  mosquitto_sub -h 127.0.0.1 -p "$plain" -v -t "$base/reply" -t "$base/probe" > "$out" &
  local listener=$!
  wait_for "the reply subscriber" sh -c \
    "mosquitto_pub -h 127.0.0.1 -p $plain -t $base/probe -m probe && grep -q '^$base/probe ' '$out'"
  pub -t "$base/command" -q 1 -m "$1"
  wait_for "a reply to $1" grep -q "^$base/reply " "$out"
  kill "$listener"; wait "$listener" 2> /dev/null || true
  sed -n "s|^$base/reply ||p" "$out"
}
reply=$(ask '{"id":1,"op":"reload"}')
echo "$reply" | grep -qF '{"id":1,"ok":false,"error":{"code":"forbidden","message":"reload: not allowed by this bridge: commands.reload is false in' ||
  fail "reload not refused: $reply"
reply=$(ask '{"id":"r2","op":"recalibrate"}')
echo "$reply" | grep -qF '"code":"forbidden","message":"recalibrate: not allowed by this bridge: commands.recalibrate is false' ||
  fail "recalibrate not refused: $reply"
reply=$(ask '{"id":3,"op":"status"}')
echo "$reply" | grep -qF '"message":"status: not a command of the bridge' || fail "status not refused: $reply"
reply=$(ask 'reload please')
echo "$reply" | grep -qF '"code":"bad_request","message":"request: not valid JSON' || fail "garbage not refused: $reply"
reply=$(ask "{\"id\":5,\"op\":\"reload\",\"pad\":\"$(head -c 2000 /dev/zero | tr '\0' x)\"}")
echo "$reply" | grep -qF '"code":"too_long"' || fail "a long command not refused: $reply"
reply=$(ask '{"id":6,"op":"reload","op":"recalibrate"}')
echo "$reply" | grep -qF 'given twice' || fail "a key given twice not refused: $reply"
"$tofcomp" query --socket "$work/tofcompd.sock" stats | grep -qx 'stats.daemon.reloads: 0' ||
  fail "a refused command reached tofcompd"
echo "commands are refused when not allowed, and malformed ones named"

# The will: kill -9, and the broker publishes "offline" (retained).
kill -9 "$bridge_pid"
wait_for "the last will" online_is offline
echo "kill -9: the will says offline"

# --- commands allowed: reload runs; SIGTERM says offline -----------------------------------------
write_config allowed "commands: {reload: true}"
start_bridge allowed bridge-allowed
wait_for "online again" online_is online
reply=$(ask '{"id":7,"op":"reload"}')
echo "$reply" | grep -qF '{"id":7,"ok":true,"message":"reloaded' || fail "reload not executed: $reply"
"$tofcomp" query --socket "$work/tofcompd.sock" stats | grep -q '^stats.daemon.reloads: 1$' ||
  fail "tofcompd did not count the reload"
reply=$(ask '{"id":8,"op":"recalibrate"}')
echo "$reply" | grep -qF 'commands.recalibrate is false' || fail "recalibrate allowed with reload: $reply"
echo "reload is executed when allowed, recalibrate still refused"

# tofcompd goes away: the status topic says so; it comes back: the bridge reads it again.
kill "$tofcompd_pid"; wait "$tofcompd_pid" || true
wait_for "status naming tofcompd's absence" sh -c "mosquitto_sub -h 127.0.0.1 -p $plain -t $base/status -C 1 -W 5 | grep -q '\"tofcompd\":null'"
start_tofcompd
wait_for "status after tofcompd returned" sh -c "mosquitto_sub -h 127.0.0.1 -p $plain -t $base/status -C 1 -W 5 | grep -q '\"state\":\"publishing'"
echo "tofcompd lost and found again"

# The broker goes away (without persistence its retained state goes too) and comes back: the
# bridge reconnects with backoff and publishes online again.
kill "$broker_pid"; wait "$broker_pid" || true
start_broker
wait_for "online after the broker's restart" online_is online
echo "broker lost and found again"

kill -TERM "$bridge_pid"
wait "$bridge_pid" || fail "the bridge did not stop cleanly"
online_is offline || fail "no offline after SIGTERM"
grep -q 'now offline' "$work/bridge-allowed.log" || fail "the bridge did not log its stop"
echo "SIGTERM: offline published, clean exit"

# --- TLS and credentials --------------------------------------------------------------------------
tls_config() {  # NAME CA PASSWORD-FILE
  {
    echo "broker:"
    echo "  host: 127.0.0.1"
    echo "  port: $tls"
    echo "  username: fleet"
    echo "  password_file: $work/$3"
    echo "  tls: {ca_file: $work/$2}"
    echo "site: testsite"
    echo "instance: left"
    echo "tofcompd: {socket: $work/tofcompd.sock}"
    echo "reconnect: {initial_s: 1, max_s: 2}"
  } > "$work/$1.yaml"
}
printf 'correct horse\n' > right.password
printf 'wrong horse\n' > wrong.password
chmod 600 right.password wrong.password
tls_sub() {
  mosquitto_sub -h 127.0.0.1 -p "$tls" --cafile "$work/ca.crt" -u fleet -P 'correct horse' "$@"
}
tls_config tls ca.crt right.password
start_bridge tls bridge-tls
wait_for "online over TLS" sh -c "[ \"\$(mosquitto_sub -h 127.0.0.1 -p $tls --cafile $work/ca.crt -u fleet -P 'correct horse' -t $base/online -C 1 -W 5)\" = online ]"
tls_sub -t "$base/status" -C 1 -W 10 | grep -q '"state"' || fail "no status over TLS"
kill -TERM "$bridge_pid"; wait "$bridge_pid" || true
echo "TLS with a password: connected"

tls_config wrong ca.crt wrong.password
start_bridge wrong bridge-wrong
wait_for "the refusal of a wrong password" grep -q 'refused the connection: Connection Refused: not authorised' "$work/bridge-wrong.log"
kill -TERM "$bridge_pid"; wait "$bridge_pid" || true
tls_config stranger other.crt right.password
start_bridge stranger bridge-stranger
wait_for "the refusal of an unknown CA" grep -q 'certificate verify failed' "$work/bridge-stranger.log"
kill -TERM "$bridge_pid"; wait "$bridge_pid" || true
grep -q 'correct horse\|wrong horse' "$work"/bridge*.log && fail "a password in the log"
chmod 644 right.password
refused_config tls "right.password: readable by every user (mode o+r)"
echo "a wrong password, an unknown CA and a readable password file are refused clearly"
echo "the MQTT bridge holds"
