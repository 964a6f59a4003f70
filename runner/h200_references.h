// Shared by the tests that replay the NVIDIA H200's recorded values against the reference's device
// ranges (runner/h200_filter_test.cpp, runner/visualize_device_test.cpp): each case's reference
// image with device allowances asked for with the H200's precision, computed once per case.
#pragma once

#include <map>
#include <string>

#include "core/pipeline.h"
#include "runner/case_loader.h"

namespace hdrc::test {

// The H200's precision as its run of 2026-11-27 recorded it (driver 580.159.04):
// subTexelPrecisionBits 8, mipmapPrecisionBits 8, float16 stores round to nearest even.
inline void set_h200_precision(ResolvedCase& rc) {
  rc.device_allowances = true;
  rc.device.sub_texel_bits = 8;
  rc.device.mipmap_bits = 8;
  rc.device.fp16_rte = true;
}

// The reference images of the repository's cases with the H200's device ranges, by case id.
class H200References {
 public:
  explicit H200References(std::string cases_dir) : loaded_(load_cases(cases_dir)) {}

  // The image of case `id` (its pipeline's reference), or nullptr with `*error` set.
  const Image* get(const std::string& id, std::string* error) {
    if (auto it = images_.find(id); it != images_.end()) return &it->second;
    const Case* found = nullptr;
    for (const Case& c : loaded_.cases)
      if (c.id == id) found = &c;
    if (found == nullptr) {
      *error = "no case " + id;
      return nullptr;
    }
    auto rc = resolve_case(*found);
    if (!rc) {
      *error = rc.error().to_string();
      return nullptr;
    }
    set_h200_precision(*rc);
    auto img = pipeline_of(*found->stage).reference(*rc, false);
    if (!img) {
      *error = img.error().to_string();
      return nullptr;
    }
    return &images_.emplace(id, std::move(*img)).first->second;
  }

 private:
  LoadedCases loaded_;
  std::map<std::string, Image> images_;
};

}  // namespace hdrc::test
