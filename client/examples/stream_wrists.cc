// A live reconstruction through the SDK: wrist samples read from stdin as a tracker would deliver
// them ("time lx ly lz rx ry rz" per line: seconds, metres, Y up), streamed with a fixed lag of 5
// frames; each frame's pelvis and ankles are printed as soon as the server decides it.
//
//   MOCAP_API_KEY=mk_... mocap_stream_example 127.0.0.1:50051 walks < wrists.txt
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>

#include <mocap/client.h>

namespace {

mocap::v1::Vec3 Vec(double x, double y, double z) {
  mocap::v1::Vec3 v;
  v.set_x(static_cast<float>(x));
  v.set_y(static_cast<float>(y));
  v.set_z(static_cast<float>(z));
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: MOCAP_API_KEY=... " << argv[0] << " ADDRESS DATABASE < wrists.txt\n";
    return 2;
  }
  const char* key = std::getenv("MOCAP_API_KEY");
  auto client = mocap::client::Client::Connect(argv[1], {.api_key = key ? key : ""});
  if (!client.ok()) {
    std::cerr << client.status() << "\n";
    return 1;
  }
  mocap::v1::SessionConfig config;
  config.set_database(argv[2]);
  config.mutable_fixed_lag()->set_lag_frames(5);
  auto stream = (*client)->OpenReconstruction(config);  // waits for the server's `started`
  if (!stream.ok()) {
    std::cerr << stream.status() << "\n";
    return 1;
  }
  std::cerr << "session " << (*stream)->started().session_id() << ": " << (*stream)->started().skeleton().joints_size()
            << " joints at " << (*stream)->started().frame_rate() << " fps\n";

  // Frames are read on their own thread while samples are written: the server reads the next
  // samples only once its replies have been delivered.
  std::thread reader([&] {
    while (true) {
      auto reply = (*stream)->Read();
      if (!reply.ok() || !*reply) return;  // the summary arrived, or the call ended
      if ((*reply)->has_rejected()) std::cerr << "sample refused: " << (*reply)->rejected().reason() << "\n";
      for (const mocap::v1::Frame& f : (*reply)->frames().frames()) {
        std::cout << f.time() << "  pelvis " << f.pelvis_position().x() << ' ' << f.pelvis_position().y() << ' '
                  << f.pelvis_position().z() << "  ankles " << f.left_ankle().y() << ' '
                  << f.right_ankle().y()
                  // How far the pelvis and an ankle are expected to be off (docs/method.md "Confidence").
                  << "  expected error pelvis " << f.expected_error().pelvis() << " ankle "
                  << f.expected_error().left_ankle() << "\n";
      }
    }
  });
  for (std::string line; std::getline(std::cin, line);) {
    std::istringstream fields(line);
    double t, lx, ly, lz, rx, ry, rz;
    if (!(fields >> t >> lx >> ly >> lz >> rx >> ry >> rz)) continue;
    mocap::v1::WristSample sample;
    sample.set_time(t);
    *sample.mutable_left() = Vec(lx, ly, lz);
    *sample.mutable_right() = Vec(rx, ry, rz);
    if (!(*stream)->Write({sample}).ok()) break;  // the session ended: Finish says why
  }
  (*stream)->CloseInput().IgnoreError();
  reader.join();
  auto summary = (*stream)->Finish();
  if (!summary.ok()) {
    std::cerr << summary.status() << "\n";
    return 1;
  }
  std::cerr << summary->frames() << " frames, " << summary->rejected_samples() << " samples refused\n";
  return 0;
}
