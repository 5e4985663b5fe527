// The near-far term of a perspective projection, -(k f n) / (f - n) (glm perspectiveRH_ZO: k = 1;
// glm 0.9.6 GL-form perspective: k = 2; PR&C D3D11 Listing 11.12's ProjectionB: k = 1), computed
// so that it stays finite and exact where the product f n alone would leave the binary32 range.
#pragma once

#include <cmath>
#include <limits>

namespace tessera {

// -(k f n) / (f - n) for finite f > n >= 0, evaluated as ((k f) n) / (f - n) in binary32.
// Ordinary cameras keep these bits: the power-of-two rescue below only runs where |k f n| is not
// a finite normal float (a world of scale 1e20, near 1e19 and far 1e22: f n = 1e41 > 3.4e38, the
// term became -inf and the inverse projection NaN; a world of scale 1e-20: f n = 1e-39 is
// subnormal and loses bits). Then f and n are both scaled by 2^-e (e = f's binary exponent, so
// f' in [0.5, 1)), the term is computed on f', n' and scaled back by 2^e: every operation
// commutes exactly with a power of two while no intermediate leaves the normal range, so the
// result is the correctly rounded chain of an unbounded-exponent binary32 (IEEE 754 §4.3).
inline float nearFarTerm(float farZ, float nearZ, float k) {
    const float product = k * farZ * nearZ;
    const float direct = -product / (farZ - nearZ);
    const float magnitude = std::fabs(product);
    if (nearZ == 0.0f || (std::isfinite(magnitude) && magnitude >= std::numeric_limits<float>::min()) || !std::isfinite(farZ))
        return direct;
    int exponent = 0;
    (void)std::frexp(farZ, &exponent);
    const float farScaled = std::ldexp(farZ, -exponent), nearScaled = std::ldexp(nearZ, -exponent);
    return std::ldexp(-(k * farScaled * nearScaled) / (farScaled - nearScaled), exponent);
}

} // namespace tessera
