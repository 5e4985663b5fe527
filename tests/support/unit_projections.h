// Exact inverse projections for hand-derived tests of the tile math: with P11 = P22 = 1 (a
// 90-degree square frustum) every tile corner and plane is exact in binary32.
#pragma once

#include <glm/glm.hpp>

namespace tessera::test {

// The inverse of 3dgep's GL-form projection with n = 1, f = 2 ([2][2] = -3, [2][3] = -1,
// [3][2] = -4): x = X, y = Y, z = -W, w = -0.25 Z + 0.75 W. ndc z = -1 maps to view (x, y, -1);
// ScreenToView(0, 0, D, 1).z = -1 / (0.75 - 0.25 D): D = 0 -> -4/3 (= -2fn/(f+n), the demo's
// near clip), D = 0.25 -> -16/11, D = 1 -> -2 (far).
inline glm::mat4 inverseGlFormUnit() {
    glm::mat4 m(0.0f);
    m[0][0] = 1.0f;
    m[1][1] = 1.0f;
    m[3][2] = -1.0f;
    m[2][3] = -0.25f;
    m[3][3] = 0.75f;
    return m;
}

} // namespace tessera::test
