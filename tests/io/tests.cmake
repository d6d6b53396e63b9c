# The gzip tests write and cut gzip members with zlib directly.
target_link_libraries(swba_test_io PRIVATE ZLIB::ZLIB)
