#include "proprio/features/image_set.hpp"

#include <gtest/gtest.h>

#include "test_util.hpp"

namespace proprio::features {
namespace {

namespace fs = std::filesystem;
using test::expect_error;

TEST(ImageSet, FolderPerClass) {
  const fs::path root = test::temp_path("set");
  fs::remove_all(root);
  for (const char* f :
       {"mug/b.png", "mug/a.JPG", "mug/notes.txt", "ball/x.jpeg", "empty/.keep", ".hidden/y.png"}) {
    fs::create_directories((root / f).parent_path());
    test::spill(root / f, "x");
  }
  const auto s = read_image_set(root);
  EXPECT_EQ(s.classes, (std::vector<std::string>{"ball", "mug"}));
  ASSERT_EQ(s.images.size(), 3U);
  EXPECT_EQ(s.images[0].filename(), "x.jpeg");
  EXPECT_EQ(s.images[1].filename(), "a.JPG");
  EXPECT_EQ(s.images[2].filename(), "b.png");
  EXPECT_EQ(s.labels, (std::vector<int>{0, 1, 1}));
}

TEST(ImageSet, BadInput) {
  const fs::path root = test::temp_path("empty_set");
  fs::remove_all(root);
  fs::create_directories(root / "cls");
  expect_error([&] { read_image_set(root); }, "no images");
  expect_error([&] { read_image_set(root / "missing"); }, "not a directory");
}

}  // namespace
}  // namespace proprio::features
