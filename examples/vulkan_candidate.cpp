// An example candidate for `hdrconform verify --candidate-cmd`: renders one exported case with
// hdrconform's own Vulkan engine, as a port of the pipeline would with its own renderer.
//
//   vulkan_candidate --params DIR/params.json --output OUT.exr [--device NAME|INDEX]
//                    [--shader-dir DIR]
//
// It reads only what `hdrconform export` writes (params.json and the images it names), never the
// case files: this is the contract a port has to meet. Exit status 0 when OUT.exr was written,
// 1 on any error (printed on stderr).
#include <cstdio>
#include <string>

#include "core/image.h"
#include "gpu/vulkan_engine.h"
#include "runner/export.h"

int main(int argc, char** argv) {
  std::string params, output;
  hdrc::gpu::VulkanOptions vk;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    if (key == "--params") {
      params = argv[i + 1];
    } else if (key == "--output") {
      output = argv[i + 1];
    } else if (key == "--device") {
      vk.device = argv[i + 1];
    } else if (key == "--shader-dir") {
      vk.shader_dir = argv[i + 1];
    } else {
      std::fprintf(stderr, "vulkan_candidate: unknown option %s\n", key.c_str());
      return 1;
    }
  }
  if (params.empty() || output.empty() || argc % 2 == 0) {
    std::fprintf(stderr,
                 "usage: vulkan_candidate --params params.json --output out.exr [--device D] "
                 "[--shader-dir DIR]\n");
    return 1;
  }
  auto rc = hdrc::load_exported_case(params);
  if (!rc) {
    std::fprintf(stderr, "vulkan_candidate: %s\n", rc.error().to_string().c_str());
    return 1;
  }
  hdrc::gpu::VulkanEngine engine(vk);
  if (hdrc::Status st = engine.init(); !st) {
    std::fprintf(stderr, "vulkan_candidate: %s\n", st.error().to_string().c_str());
    return 1;
  }
  auto image = engine.run(*rc);
  if (!image) {
    std::fprintf(stderr, "vulkan_candidate: %s: %s\n", rc->spec.id.c_str(),
                 image.error().to_string().c_str());
    return 1;
  }
  if (hdrc::Status st = hdrc::write_exr(output, *image); !st) {
    std::fprintf(stderr, "vulkan_candidate: %s\n", st.error().to_string().c_str());
    return 1;
  }
  return 0;
}
