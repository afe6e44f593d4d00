// The target that builds the tests' precompiled headers (tests/CMakeLists.txt lowpair_test_pch*); no code.
