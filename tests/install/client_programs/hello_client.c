/* A C program against the installed libtofcomp-client (tests/install/client_install_test.sh):
 * connects to the socket named on the command line, prints the protocol version the daemon's
 * hello stated, subscribes to beams 178..182 as compact frames and prints one scan's beams. */
#include <stdio.h>
#include <tofcomp/tofcomp_client.h>

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: %s SOCKET\n", argv[0]);
    return 2;
  }
  tofcomp_connection* daemon = NULL;
  if (tofcomp_connect(argv[1], 30000, &daemon) != TOFCOMP_OK) {
    fprintf(stderr, "hello_client: %s\n", tofcomp_last_error());
    return 1;
  }
  int major = 0, minor = 0;
  const char* version = NULL;
  tofcomp_hello(daemon, &major, &minor, &version);
  printf("C: libtofcomp-client %s, tofcompd %s, protocol %d.%d\n", tofcomp_client_version(),
         version, major, minor);
  tofcomp_scan* scan = NULL;
  if (tofcomp_subscribe(daemon, 178, 182, 1, TOFCOMP_FORMAT_COMPACT, 30000) != TOFCOMP_OK ||
      tofcomp_next_scan(daemon, 30000, &scan) != TOFCOMP_OK) {
    fprintf(stderr, "hello_client: no scan: %s\n", tofcomp_last_error());
    tofcomp_disconnect(daemon);
    return 1;
  }
  const tofcomp_scan_info* info = tofcomp_scan_get_info(scan);
  size_t count = 0;
  const tofcomp_beam* beams = tofcomp_scan_beams(scan, &count);
  printf("C: scan %llu of %u beams\n", (unsigned long long)info->sequence, info->beam_count);
  for (size_t i = 0; i < count; ++i) {
    printf("C: beam %u compensated %.2f mm flags %u\n", beams[i].index, beams[i].compensated_mm,
           (unsigned)beams[i].flags);
  }
  tofcomp_scan_free(scan);
  tofcomp_disconnect(daemon);
  return 0;
}
