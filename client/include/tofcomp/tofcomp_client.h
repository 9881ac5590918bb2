/* libtofcomp-client's C API: read tofcompd's compensated scans from its Unix socket
 * (docs/protocol.md) or its shared-memory ring (docs/shm-ring.md), from C or any language with a
 * C foreign-function interface (the Python module tofcomp_client binds it with ctypes).
 *
 * Handles are opaque and belong to the caller until closed or freed; one handle is used by one
 * thread at a time. Every function that can fail returns a status: TOFCOMP_OK (0), TOFCOMP_NO_SCAN
 * (1, not a failure), or a negative TOFCOMP_ERR_*; after a failure tofcomp_last_error() gives the
 * message of this thread's last failure, naming what failed and why. */
#ifndef TOFCOMP_CLIENT_H
#define TOFCOMP_CLIENT_H

#include <stddef.h>
#include <stdint.h>

#include "tofcomp/version.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TOFCOMP_DEFAULT_SOCKET_PATH "/run/tofcompd/tofcompd.sock"
#define TOFCOMP_DEFAULT_RING_NAME "/tofcompd"
#define TOFCOMP_MAX_MODES 4    /* mode posteriors carried per beam */
#define TOFCOMP_ALL_BEAMS (-1) /* as first and last: every beam of the scan */

enum tofcomp_status {
  TOFCOMP_OK = 0,
  TOFCOMP_NO_SCAN = 1,                /* no scan within the timeout, or none new in the ring */
  TOFCOMP_ERR_INVALID_ARGUMENT = -1,  /* a null handle, a bad range, a bad format */
  TOFCOMP_ERR_CONNECT = -2,           /* the socket cannot be connected to */
  TOFCOMP_ERR_PROTOCOL_VERSION = -3,  /* the daemon speaks another major protocol version */
  TOFCOMP_ERR_TIMEOUT = -4,           /* no answer within the timeout */
  TOFCOMP_ERR_CLOSED = -5,            /* the daemon closed the connection */
  TOFCOMP_ERR_DAEMON = -6,            /* the daemon answered with an error: tofcomp_last_daemon_code */
  TOFCOMP_ERR_BAD_DATA = -7,          /* what arrived is not a valid reply, scan or frame */
  TOFCOMP_ERR_RING = -8,              /* the ring cannot be opened or read */
  TOFCOMP_ERR_INTERNAL = -9           /* anything else (out of memory) */
};

/* How a subscription's scans are sent: JSON lines, or compact binary frames (compensated
 * ranges and flags only; docs/protocol.md, "Compact frames"). */
enum tofcomp_format { TOFCOMP_FORMAT_JSON = 0, TOFCOMP_FORMAT_COMPACT = 1 };

/* Per-beam flag bits (docs/protocol.md, "The scan object"). */
enum tofcomp_beam_flag {
  TOFCOMP_FLAG_NO_ECHO = 1 << 0,
  TOFCOMP_FLAG_UNCALIBRATED = 1 << 1,
  TOFCOMP_FLAG_TEMPERATURE_STALE = 1 << 2,
  TOFCOMP_FLAG_WINDOW_RESTARTING = 1 << 3,
  TOFCOMP_FLAG_CHANGE_DETECTED = 1 << 4,
  TOFCOMP_FLAG_OUTLIER = 1 << 5,
  TOFCOMP_FLAG_TEMPERATURE_EXTRAPOLATED = 1 << 6
};

/* A scan's header. A value that does not exist is NaN. */
typedef struct tofcomp_scan_info {
  uint64_t sequence;        /* the daemon's scan counter, from 0, no gaps */
  uint64_t device_sequence; /* the host driver's scan counter */
  int64_t timestamp_ns;     /* host receive time, CLOCK_REALTIME, ns since the epoch */
  double junction_c;        /* junction temperature estimate, degrees C */
  double junction_std_c;    /* its standard deviation */
  double case_c;            /* the latest accepted case reading */
  double start_angle_deg;   /* angle of beam 0 */
  double resolution_deg;    /* angle step between beams */
  uint32_t calibration_id;  /* increments at each calibration swap; 0 = none */
  uint32_t beam_count;      /* beams in the scan (those carried: tofcomp_scan_beams) */
  /* When the rays were measured (docs/protocol.md "Time"): beam i's ray comes
   * (i mod n) * turn_period_ns + (i / n) * ray_interval_ns after first_ray_ns, n the interlaced
   * turns; interlaced_turns 0: unknown (a recording's scans). */
  int64_t first_ray_ns;      /* beam 0's ray, CLOCK_REALTIME, ns since the epoch */
  double ray_interval_ns;    /* between consecutive rays of one mirror turn */
  double turn_period_ns;     /* one mirror turn */
  uint32_t interlaced_turns; /* turns one scan interlaces (1, 2 or 4); 0: unknown */
  uint32_t reserved;         /* 0 */
} tofcomp_scan_info;

/* One beam. Distances in mm; a value that does not exist, or that a compact frame does not carry
 * (raw, window, modes), is NaN (mode_count 0). */
typedef struct tofcomp_beam {
  uint32_t index;             /* the beam's index in the scan */
  uint16_t flags;             /* tofcomp_beam_flag bits */
  uint8_t mode_count;         /* modes of the calibration (0 when uncalibrated or not sent) */
  uint8_t most_probable_mode; /* the most probable lasing mode */
  double raw_mm;              /* the range the device reported */
  double compensated_mm;      /* the compensated range */
  double window_mm;           /* the sliding-window estimate */
  double window_std_mm;       /* its standard deviation */
  float mode_posterior[TOFCOMP_MAX_MODES]; /* P(mode i | this range), mode_count of them */
} tofcomp_beam;

typedef struct tofcomp_connection tofcomp_connection;
typedef struct tofcomp_ring tofcomp_ring;
typedef struct tofcomp_scan tofcomp_scan;

/* The library's version as linked ("0.1.0"; TOFCOMP_CLIENT_VERSION_STRING as compiled). */
const char* tofcomp_client_version(void);
/* This thread's last failure: its message ("" when none). Valid until the next call that fails
 * in this thread. */
const char* tofcomp_last_error(void);
/* After TOFCOMP_ERR_DAEMON: the daemon's error code (bad_range, unavailable, forbidden, ...). */
const char* tofcomp_last_daemon_code(void);

/* Connects to the socket at path (NULL: the user's own daemon's when it runs, else
 * TOFCOMP_DEFAULT_SOCKET_PATH, as `tofcomp query` chooses) and exchanges hello: a
 * daemon whose major protocol version differs is refused (TOFCOMP_ERR_PROTOCOL_VERSION, the
 * message naming both versions). timeout_ms bounds the connection and the hello. */
int tofcomp_connect(const char* path, int timeout_ms, tofcomp_connection** out);
void tofcomp_disconnect(tofcomp_connection* connection);
/* What the daemon's hello stated. daemon_version stays valid while the connection is open. */
int tofcomp_hello(const tofcomp_connection* connection, int* protocol_major, int* protocol_minor,
                  const char** daemon_version);
/* The latest scan, beams first..last (inclusive; TOFCOMP_ALL_BEAMS for both: every beam). */
int tofcomp_latest(tofcomp_connection* connection, int first, int last, int timeout_ms,
                   tofcomp_scan** out);
/* Subscribes to the scans whose sequence is a multiple of every, beams first..last, in format
 * (enum tofcomp_format). */
int tofcomp_subscribe(tofcomp_connection* connection, int first, int last, unsigned every,
                      int format, int timeout_ms);
/* The next scan of the subscription; TOFCOMP_NO_SCAN when none came within timeout_ms. */
int tofcomp_next_scan(tofcomp_connection* connection, int timeout_ms, tofcomp_scan** out);
int tofcomp_unsubscribe(tofcomp_connection* connection, int timeout_ms);
/* Any request, a JSON object (docs/protocol.md), and its reply line; free it with
 * tofcomp_free_string. An error reply is TOFCOMP_ERR_DAEMON (*reply_json is then NULL). */
int tofcomp_call(tofcomp_connection* connection, const char* request_json, int timeout_ms,
                 char** reply_json);
void tofcomp_free_string(char* text);

/* Opens the shared-memory ring name (NULL: the user's own daemon's when it runs, else
 * TOFCOMP_DEFAULT_RING_NAME) read-only, checking its
 * owner and header. Reading starts at the next scan published. */
int tofcomp_ring_open(const char* name, tofcomp_ring** out);
void tofcomp_ring_close(tofcomp_ring* ring);
/* The newest scan; TOFCOMP_NO_SCAN while none was published. */
int tofcomp_ring_latest(tofcomp_ring* ring, tofcomp_scan** out);
/* The next scan since the last one returned, oldest first; TOFCOMP_NO_SCAN when none is new. */
int tofcomp_ring_next(tofcomp_ring* ring, tofcomp_scan** out);
/* Scans overwritten before this reader copied them, since it was opened. */
uint64_t tofcomp_ring_lost(const tofcomp_ring* ring);

/* Decodes one compact frame (docs/protocol.md, "Compact frames"); every length is checked. */
int tofcomp_decode_compact(const void* bytes, size_t size, tofcomp_scan** out);

void tofcomp_scan_free(tofcomp_scan* scan);
/* The scan's header; valid while the scan is. */
const tofcomp_scan_info* tofcomp_scan_get_info(const tofcomp_scan* scan);
/* The beams carried (a contiguous range of indices), *count of them; valid while the scan is. */
const tofcomp_beam* tofcomp_scan_beams(const tofcomp_scan* scan, size_t* count);

#ifdef __cplusplus
}
#endif

#endif
