#Tests of graph cuts and the Fitzpatrick& Metta baseline.
proprio_test(segmentation_baseline_test SOURCES graph_cut_test.cpp fm_baseline_test.cpp LIBS
                 proprio::segmentation proprio::episode)
