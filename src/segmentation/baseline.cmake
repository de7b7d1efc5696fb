# The baseline half of the segmentation module: graph cuts (Boost.Graph's Boykov-Kolmogorov
# max-flow, header-only: no link dependency) and the Fitzpatrick & Metta 2003 baseline.
list(APPEND PROPRIO_SEG_BASELINE_SOURCES graph_cut.cpp fm_baseline.cpp)
