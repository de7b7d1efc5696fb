# Motion-Likelihood half of the segmentation module (thesis Ch 4).
list(APPEND PROPRIO_SEG_ML_SOURCES
  ml_segmentation.cpp
  motion_models.cpp
  optical_flow.cpp
  region_tracker.cpp
  sparse_segmentation.cpp)
