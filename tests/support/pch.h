// The precompiled header of every test executable (tests/CMakeLists.txt): the headers nearly
// every test includes (doctest, the standard library, glm, nlohmann::json), parsed once per
// executable instead of once per test file. Third-party and standard headers only: a tessera
// header here would put its names into test files that define their own (a test's `Frame`).
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>
