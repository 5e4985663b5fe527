// D3D11_COMPARISON_FUNC and its evaluation, shared by the depth and stencil tests.
// D3D11.3 §17.? "Depth/Stencil Test": the incoming value is the left operand, the stored
// value the right one: pass = (src OP dst). For stencil, src = ref & readMask.
#pragma once

#include <cstdint>

namespace tessera {

enum class ComparisonFunc : std::uint8_t {
    Never = 1, Less, Equal, LessEqual, Greater, NotEqual, GreaterEqual, Always
};

// True when `src OP dst` holds. Works on any totally ordered type; for floats, NaN compares
// false under every operator except NotEqual and Always (IEEE), as on hardware.
template <class T>
constexpr bool compare(ComparisonFunc func, T src, T dst) {
    switch (func) {
    case ComparisonFunc::Never: return false;
    case ComparisonFunc::Less: return src < dst;
    case ComparisonFunc::Equal: return src == dst;
    case ComparisonFunc::LessEqual: return src <= dst;
    case ComparisonFunc::Greater: return src > dst;
    case ComparisonFunc::NotEqual: return src != dst;
    case ComparisonFunc::GreaterEqual: return src >= dst;
    case ComparisonFunc::Always: return true;
    }
    return false;
}

} // namespace tessera
