// Specular power packing of the 3dgep G-buffer: log2(p)/10.5 into an UNORM8 alpha and back
// (3dgep article §3.1.1.4). The float -> UNORM step is the project's D3D11.3 conversion.
#include <tessera/gbuffer/specular_power_packing.h>

#include <tessera/buffers/conversion.h>
#include <tessera/math/det_math.h>

namespace tessera {

// log2 / exp2 from det_math.h (libm-independent, within 1 ulp of correctly rounded): the HLSL
// intrinsics' values are GPU-dependent, tessera fixes these.
float packSpecularPower(float specularPower) {
    return detLog2(specularPower) / kSpecularPowerLog2Range;
}

float unpackSpecularPower(float packed) {
    return detExp2(packed * kSpecularPowerLog2Range);
}

std::uint8_t specularPowerCode(float specularPower) {
    return static_cast<std::uint8_t>(convert::floatToUnorm(packSpecularPower(specularPower), 8));
}

float roundTripSpecularPower(float specularPower) {
    return unpackSpecularPower(convert::unormToFloat(specularPowerCode(specularPower), 8));
}

} // namespace tessera
