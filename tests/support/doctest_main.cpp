// The doctest entry point shared by every test executable (one per *_test.cpp file).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
