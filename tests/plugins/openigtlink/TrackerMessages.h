#pragma once
// What a tracker on Debian's libopenigtlink (PLUS, 3D Slicer) sends and reads:
// TRANSFORMs of its tool, and the SENSORs the server sends back. Shared by the
// device's tests and the benchmark's client, igtl_tracker_client.
#include <igtlClientSocket.h>
#include <igtlMessageHeader.h>
#include <igtlSensorMessage.h>
#include <igtlTransformMessage.h>

#include <cstring>

namespace trephine::igtltest {

// A TRANSFORM named `name`: no rotation, the tool's tip at (x, y, z) mm.
// False when the socket did not take it.
inline bool sendPose(igtl::ClientSocket& socket, const char* name, float x, float y, float z) {
  auto message = igtl::TransformMessage::New();
  message->SetDeviceName(name);
  igtl::Matrix4x4 m;
  igtl::IdentityMatrix(m);
  m[0][3] = x;
  m[1][3] = y;
  m[2][3] = z;
  message->SetMatrix(m);
  message->Pack();
  return socket.Send(message->GetPackPointer(), message->GetPackSize()) == 1;
}

// The next SENSOR on the socket (other messages are skipped); `message` is
// null once the connection has ended, and `unpacked` false for a SENSOR whose
// body does not unpack.
struct ReceivedSensor {
  igtl::SensorMessage::Pointer message;
  bool unpacked = false;
};

inline ReceivedSensor receiveSensor(igtl::ClientSocket& socket) {
  for (;;) {
    auto header = igtl::MessageHeader::New();
    header->InitPack();
    if (socket.Receive(header->GetPackPointer(), header->GetPackSize()) != header->GetPackSize()) return {};
    header->Unpack();
    if (std::strcmp(header->GetDeviceType(), "SENSOR") != 0) {
      socket.Skip(header->GetBodySizeToRead(), 0);
      continue;
    }
    auto sensor = igtl::SensorMessage::New();
    sensor->SetMessageHeader(header);
    sensor->AllocatePack();
    if (socket.Receive(sensor->GetPackBodyPointer(), sensor->GetPackBodySize()) != sensor->GetPackBodySize())
      return {};
    const bool unpacked = sensor->Unpack(1) == igtl::MessageHeader::UNPACK_BODY;
    return {sensor, unpacked};
  }
}

}  // namespace trephine::igtltest
