# Tests of the Motion-Likelihood half of the segmentation module.
proprio_test(segmentation_ml_test
  SOURCES ml_segmentation_test.cpp
  LIBS proprio::segmentation proprio::episode proprio::core)

# Scoring over the simulator's thesis-ch5 dataset (minutes; skipped when it is absent).
add_executable(segmentation_ml_dataset_test ml_dataset_test.cpp)
target_link_libraries(segmentation_ml_dataset_test PRIVATE proprio::segmentation proprio::episode
                      GTest::gtest GTest::gtest_main)
proprio_warnings(segmentation_ml_dataset_test)
add_test(NAME segmentation_ml_dataset COMMAND segmentation_ml_dataset_test)
set_tests_properties(segmentation_ml_dataset PROPERTIES LABELS slow TIMEOUT 3600)
