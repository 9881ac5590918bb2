// A C++ program against the installed libtofcomp-client (tests/install/client_install_test.sh):
// connects to the socket named on the command line, prints the protocol version the daemon's
// hello stated and the latest scan's beams 178..182, then one scan from the ring named second.
#include <chrono>
#include <iostream>
#include <thread>
#include <tofcomp/client.hpp>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: " << argv[0] << " SOCKET RING\n";
    return 2;
  }
  try {
    const std::chrono::seconds timeout(30);
    tofcomp::client::Connection daemon(argv[1], timeout);
    std::cout << "C++: libtofcomp-client " << tofcomp::client::library_version() << ", "
              << daemon.hello().daemon << " " << daemon.hello().daemon_version << ", protocol "
              << daemon.hello().protocol_major << "." << daemon.hello().protocol_minor << "\n";
    const tofcomp::client::Scan scan = daemon.latest(tofcomp::client::BeamRange{178, 182}, timeout);
    std::cout << "C++: scan " << scan.info.sequence << " of " << scan.info.beam_count << " beams\n";
    for (const auto& beam : scan.beams) {
      std::cout << "C++: beam " << beam.index << " raw " << beam.raw_mm << " mm\n";
    }
    tofcomp::client::Ring ring(argv[2]);
    const auto latest = ring.latest();
    if (!latest) throw std::runtime_error("the ring holds no scan");
    std::cout << "C++: ring " << ring.name() << " scan " << latest->info.sequence << " of "
              << latest->beams.size() << " beams\n";
  } catch (const tofcomp::client::Error& e) {
    std::cerr << "hello_client: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
