# Tests of the Motion-Likelihood half of the segmentation module.
proprio_test(segmentation_ml_test
  SOURCES ml_segmentation_test.cpp
  LIBS proprio::segmentation proprio::episode proprio::core)
