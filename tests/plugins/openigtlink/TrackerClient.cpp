// igtl_tracker_client: a tracker on Debian's libopenigtlink, as PLUS or 3D
// Slicer would be, for tools/bench_igtlink.py: sends TRANSFORMs named "Tool"
// at HZ for SECONDS (the point at X Y Z mm), reads every SENSOR that comes
// back, and prints what it saw as one JSON object.
//
//   igtl_tracker_client PORT HZ SECONDS X Y Z

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#include "tests/plugins/openigtlink/TrackerMessages.h"

int main(int argc, char** argv) {
  if (argc != 7) {
    std::fprintf(stderr, "usage: igtl_tracker_client PORT HZ SECONDS X Y Z\n");
    return 2;
  }
  const int port = std::atoi(argv[1]);
  const double hz = std::atof(argv[2]), seconds = std::atof(argv[3]);
  const float x = static_cast<float>(std::atof(argv[4])), y = static_cast<float>(std::atof(argv[5])),
              z = static_cast<float>(std::atof(argv[6]));
  auto socket = igtl::ClientSocket::New();
  // The simulation may still be loading: try for 30 s.
  bool connected = false;
  for (int i = 0; i < 300 && !connected; ++i) {
    connected = socket->ConnectToServer("127.0.0.1", port) == 0;
    if (!connected) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (!connected) {
    std::fprintf(stderr, "igtl_tracker_client: no server on 127.0.0.1:%d\n", port);
    return 1;
  }
  std::atomic<long> sensors{0}, bad{0};
  std::atomic<double> lastZ{NAN};
  std::thread reader([&] {
    for (;;) {
      const trephine::igtltest::ReceivedSensor received = trephine::igtltest::receiveSensor(*socket);
      if (!received.message) return;
      const auto& sensor = received.message;
      if (!received.unpacked || sensor->GetLength() != 3) {
        ++bad;
        continue;
      }
      lastZ = sensor->GetValue(2);
      ++sensors;
    }
  });
  const auto start = std::chrono::steady_clock::now();
  const auto period = std::chrono::duration<double>(1.0 / hz);
  long sent = 0;
  for (auto next = start; std::chrono::steady_clock::now() - start < std::chrono::duration<double>(seconds);
       next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period)) {
    std::this_thread::sleep_until(next);
    if (!trephine::igtltest::sendPose(*socket, "Tool", x, y, z)) break;
    ++sent;
  }
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The server closes the connection when its run ends; the reader ends then.
  reader.join();
  std::printf("{\"transforms_sent\": %ld, \"transform_hz\": %.1f, \"sensors_received\": %ld, \"bad_sensors\": %ld, "
              "\"last_force_z_N\": %.6f}\n",
              sent, sent / elapsed, sensors.load(), bad.load(), lastZ.load());
  return 0;
}
