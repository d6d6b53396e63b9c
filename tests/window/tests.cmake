# The range-bearing graph's private parts (LandmarkStore, ReadingGate, LandmarkPredictor's
# match_readings) are tested alone, through their headers in modules/estimators/src.
target_include_directories(swba_test_window PRIVATE ${CMAKE_SOURCE_DIR}/modules/estimators/src)
