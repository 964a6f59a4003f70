// core/image.h written_images: the run's images handed to its report in memory. What is taken is
// what read_image would return for the file written, each image is taken once, the capacity
// bounds what is kept, and a deleted file's image is forgotten.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>

#include "core/image.h"

namespace {

namespace fs = std::filesystem;
namespace wi = hdrc::written_images;

hdrc::Image pattern(int w, int h) {
  hdrc::Image img(w, h);
  for (size_t i = 0; i < img.data.size(); ++i)
    img.data[i] = std::sin(0.37 * static_cast<double>(i)) * 1e3 + 1.0 / 3.0;  // not float-exact
  img.data[5] = std::numeric_limits<double>::quiet_NaN();
  img.data[6] = -std::numeric_limits<double>::infinity();
  return img;
}

struct WrittenImages : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("hdrc_written_" + std::to_string(::getpid()));
  void SetUp() override {
    fs::create_directories(dir);
    wi::clear();
  }
  void TearDown() override {
    wi::set_capacity(0);
    wi::clear();
    fs::remove_all(dir);
  }
};

TEST_F(WrittenImages, TakenImageIsWhatTheFileReadsBackOnce) {
  wi::set_capacity(size_t{1} << 20);
  const hdrc::Image img = pattern(7, 5);
  const std::string path = (dir / "a.exr").string();
  ASSERT_TRUE(hdrc::write_exr(path, img, 1));
  wi::keep(path, img);
  EXPECT_EQ(wi::bytes_kept(), img.data.size() * sizeof(float));
  // Looked up by the same path spelled differently (lexically normalised).
  auto kept = wi::take((dir / "." / "a.exr").string());
  ASSERT_TRUE(kept);
  auto read = hdrc::read_image(path);
  ASSERT_TRUE(read);
  ASSERT_EQ(kept->width, read->width);
  ASSERT_EQ(kept->height, read->height);
  EXPECT_EQ(0,
            std::memcmp(kept->data.data(), read->data.data(), read->data.size() * sizeof(double)));
  EXPECT_FALSE(wi::take(path));  // taken once
  EXPECT_EQ(wi::bytes_kept(), 0u);
}

TEST_F(WrittenImages, CapacityBoundsWhatIsKeptAndForgetDropsIt) {
  const hdrc::Image img = pattern(16, 16);  // 4 KB as float32
  const size_t one = img.data.size() * sizeof(float);
  wi::keep((dir / "none.exr").string(), img);  // capacity 0: nothing kept
  EXPECT_FALSE(wi::take((dir / "none.exr").string()));
  wi::set_capacity(2 * one + one / 2);
  wi::keep((dir / "1.exr").string(), img);
  wi::keep((dir / "2.exr").string(), img);
  wi::keep((dir / "3.exr").string(), img);  // over the capacity: not kept
  EXPECT_EQ(wi::bytes_kept(), 2 * one);
  EXPECT_FALSE(wi::take((dir / "3.exr").string()));
  wi::keep((dir / "1.exr").string(), img);  // written again: replaced, not counted twice
  EXPECT_EQ(wi::bytes_kept(), 2 * one);
  wi::forget((dir / "2.exr").string());
  EXPECT_EQ(wi::bytes_kept(), one);
  EXPECT_FALSE(wi::take((dir / "2.exr").string()));
  EXPECT_TRUE(wi::take((dir / "1.exr").string()));
  EXPECT_EQ(wi::bytes_kept(), 0u);
}

}  // namespace
