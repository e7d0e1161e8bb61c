// Example: connect with a key, import BVH files into a database, list its clips, export one.
//   mocap_client_example ADDRESS DATABASE FILE.bvh...     (key in MOCAP_API_KEY)
#include <cstdlib>
#include <iostream>

#include <mocap/client.h>

int main(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: " << argv[0] << " ADDRESS DATABASE FILE.bvh...  (key in MOCAP_API_KEY)\n";
    return 2;
  }
  const char* key = std::getenv("MOCAP_API_KEY");
  auto client = mocap::client::Client::Connect(argv[1], {.api_key = key ? key : ""});
  if (!client.ok()) {
    std::cerr << client.status() << "\n";
    return 1;
  }
  const std::string database = argv[2];
  std::vector<std::filesystem::path> files(argv + 3, argv + argc);
  auto imported =
      (*client)->ImportFiles(database, files, {.keep_going = true}, [](const mocap::client::ImportProgress& p) {
        std::cerr << "\r" << p.files_sent << "/" << p.files_total << " files";
      });
  std::cerr << "\n";
  if (!imported.ok()) {
    std::cerr << "import failed: " << imported.status() << "\n";
    return 1;
  }
  for (const auto& file : imported->files()) {
    std::cout << file.file_name() << ": " << mocap::v1::FileResult::Outcome_Name(file.outcome()) << " " << file.error()
              << "\n";
  }
  auto clips = (*client)->ListClips(database);
  if (!clips.ok()) {
    std::cerr << clips.status() << "\n";
    return 1;
  }
  std::cout << database << " holds " << clips->size() << " clip(s)\n";
  if (!clips->empty()) {
    auto bvh = (*client)->ExportClip(database, clips->front().id());
    if (!bvh.ok()) {
      std::cerr << bvh.status() << "\n";
      return 1;
    }
    std::cout << "clip " << clips->front().id() << " exports as " << bvh->size() << " bytes of BVH\n";
  }
  return 0;
}
