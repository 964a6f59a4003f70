// libFuzzer harness: what `merge OUT DIR...` reads from its shards (runner/merge.h). The input is
// split at NUL bytes into up to four shards' results.json; each is written to its own shard
// folder and read as merge reads it (read_given_results_json: the bounded reader, then
// runner/results.schema.json), and the documents that pass are merged (merge_results: every
// cross-check of merge.h, then the merged results.json, its exit code and JUnit). The folders the
// shards ran on (shard_input_folders, from provenance.command_line and cwd) and every case image
// path (safe_image_path) are taken as merge takes them. Seeds: fuzz/corpus/merge/ (two shards of a
// small run joined by a NUL, and edits of them).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "fuzz/fuzz_files.h"
#include "runner/merge.h"
#include "runner/results.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> parts;
  for (size_t at = 0; parts.size() < 4;) {
    const size_t nul = text.find('\0', at);
    parts.push_back(text.substr(at, nul == std::string::npos ? std::string::npos : nul - at));
    if (nul == std::string::npos) break;
    at = nul + 1;
  }
  std::vector<nlohmann::ordered_json> docs;
  std::vector<std::string> dirs;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string dir = hdrc::fuzz::scratch_dir() + "/s" + std::to_string(i + 1);
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    hdrc::fuzz::write_scratch("s" + std::to_string(i + 1) + "/results.json",
                              reinterpret_cast<const uint8_t*>(parts[i].data()), parts[i].size());
    auto doc = hdrc::read_given_results_json(dir + "/results.json");
    if (!doc) {
      (void)doc.error().to_string();
      continue;
    }
    for (const std::string& f : hdrc::shard_input_folders(*doc)) (void)f.size();
    docs.push_back(std::move(*doc));
    dirs.push_back(dir);
  }
  if (docs.empty()) return 0;
  auto merged = hdrc::merge_results(docs, dirs);
  if (!merged) {
    (void)merged.error().to_string();
    return 0;
  }
  for (const auto& c : merged->doc["cases"])
    if (auto im = c.find("images"); im != c.end() && im->is_object())
      for (const auto& [name, rel] : im->items())
        if (rel.is_string()) (void)hdrc::safe_image_path(rel.get<std::string>());
  (void)merged->doc.dump();
  (void)hdrc::junit_from_results(merged->doc);
  return 0;
}
