// Topic localisation maps (thesis eqs 7.6-7.7): on an image whose left features are words of one
// topic and right features words of another, each topic's map lies over its own features.
#include "proprio/recognition/topic_localisation.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "proprio/core/error.hpp"

namespace proprio::recognition {
namespace {

features::Vocabulary one_hot_vocabulary() {
  cv::Mat w(4, features::kDescriptorLength, CV_32F, cv::Scalar(0));
  for (int j = 0; j < 4; ++j) w.at<float>(j, j) = 100.0F;
  return features::Vocabulary(w);
}

topics::LdaModel two_topics() {
  topics::LdaModel m;
  m.lambda.resize(2, 4);
  m.lambda << 10, 10, 0.01, 0.01, 0.01, 0.01, 10, 10;
  m.alpha = 0.5;
  m.eta = 0.1;
  return m;
}

/// 10 features of words 0/1 around (20, 30), 10 of words 2/3 around (80, 30).
features::Features left_right() {
  features::Features f;
  f.descriptors = cv::Mat(20, features::kDescriptorLength, CV_32F, cv::Scalar(0));
  for (int k = 0; k < 20; ++k) {
    const bool left = k < 10;
    f.keypoints.emplace_back(cv::Point2f(left ? 18.0F + k % 5 : 78.0F + k % 5, 28.0F + k % 3),
                             16.0F);
    f.descriptors.at<float>(k, (left ? 0 : 2) + k % 2) = 100.0F;
  }
  return f;
}

TEST(TopicLocalisation, EachTopicsMapLiesOverItsFeatures) {
  for (const MapWeight weight : {MapWeight::kWordGivenTopic, MapWeight::kResponsibility}) {
    TopicMapOptions o;
    o.weight = weight;
    o.sigma = 4.0;
    const TopicMaps m =
        topic_maps(left_right(), cv::Size(100, 60), two_topics(), one_hot_vocabulary(), o);
    ASSERT_EQ(m.density.size(), 2U);
    EXPECT_NEAR(m.theta(0), 0.5, 0.05);
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(cv::sum(m.density[i])[0], 1.0, 1e-9);
      EXPECT_TRUE(cv::checkRange(m.density[i]));
    }
    EXPECT_LT(m.peak[0].x, 30);
    EXPECT_GT(m.peak[1].x, 70);
    EXPECT_NEAR(m.peak[0].y, 29, 3);
    // Almost all of topic 1's density is over the right half.
    EXPECT_GT(cv::sum(m.density[1](cv::Rect(50, 0, 50, 60)))[0], 0.99);
  }
}

TEST(TopicLocalisation, AnImageWithoutFeaturesHasZeroMaps) {
  const TopicMaps m =
      topic_maps(features::Features{}, cv::Size(40, 30), two_topics(), one_hot_vocabulary());
  ASSERT_EQ(m.density.size(), 2U);
  EXPECT_EQ(cv::countNonZero(m.density[0]), 0);
  EXPECT_EQ(m.peak[1], cv::Point(-1, -1));
}

TEST(TopicLocalisation, BadInputIsAnError) {
  topics::LdaModel three = two_topics();
  three.lambda.conservativeResize(2, 3);
  EXPECT_THROW((void)topic_maps(left_right(), cv::Size(100, 60), three, one_hot_vocabulary()),
               Error);
  TopicMapOptions o;
  o.sigma = 0;
  EXPECT_THROW(
      (void)topic_maps(left_right(), cv::Size(100, 60), two_topics(), one_hot_vocabulary(), o),
      Error);
}

TEST(TopicLocalisation, WritesOneImagePerTopic) {
  const TopicMaps m =
      topic_maps(left_right(), cv::Size(100, 60), two_topics(), one_hot_vocabulary());
  const auto dir =
      std::filesystem::temp_directory_path() / ("proprio_topic_maps_" + std::to_string(::getpid()));
  const cv::Mat image(60, 100, CV_8UC3, cv::Scalar(40, 40, 40));
  const auto files = write_topic_maps(m, dir, image);
  ASSERT_EQ(files.size(), 2U);
  EXPECT_EQ(files[1].filename(), "topic_2.png");
  EXPECT_TRUE(std::filesystem::exists(files[0]));
  EXPECT_EQ(topic_map_image(m.density[0], image).size(), image.size());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace proprio::recognition
