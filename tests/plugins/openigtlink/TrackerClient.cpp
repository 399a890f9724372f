// igtl_tracker_client: a tracker on Debian's libopenigtlink, as PLUS or 3D
// Slicer would be, for tools/bench_igtlink.py: sends TRANSFORMs named "Tool"
// at HZ for SECONDS (the point at X Y Z mm), reads every SENSOR that comes
// back, and prints what it saw as one JSON object.
//
//   igtl_tracker_client PORT HZ SECONDS X Y Z
#include <igtlClientSocket.h>
#include <igtlSensorMessage.h>
#include <igtlTransformMessage.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

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
      auto header = igtl::MessageHeader::New();
      header->InitPack();
      if (socket->Receive(header->GetPackPointer(), header->GetPackSize()) != header->GetPackSize()) return;
      header->Unpack();
      if (std::strcmp(header->GetDeviceType(), "SENSOR") != 0) {
        socket->Skip(header->GetBodySizeToRead(), 0);
        continue;
      }
      auto sensor = igtl::SensorMessage::New();
      sensor->SetMessageHeader(header);
      sensor->AllocatePack();
      if (socket->Receive(sensor->GetPackBodyPointer(), sensor->GetPackBodySize()) != sensor->GetPackBodySize()) return;
      if (sensor->Unpack(1) != igtl::MessageHeader::UNPACK_BODY || sensor->GetLength() != 3) {
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
    auto message = igtl::TransformMessage::New();
    message->SetDeviceName("Tool");
    igtl::Matrix4x4 m;
    igtl::IdentityMatrix(m);
    m[0][3] = x;
    m[1][3] = y;
    m[2][3] = z;
    message->SetMatrix(m);
    message->Pack();
    if (socket->Send(message->GetPackPointer(), message->GetPackSize()) != 1) break;
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
