// Assembles DrawStates from the deferred techniques' fixed-function pass states
// (include/tessera/techniques/deferred_states.h) and the Killzone 2 query decision.
#include <tessera/techniques/deferred_states.h>

namespace tessera {

DrawState makeDrawState(const PassState& pass, const Viewport& viewport) {
    DrawState st;
    st.rasterizer = pass.rasterizer;
    st.depthStencil = pass.depthStencil;
    st.stencilRef = pass.stencilRef;
    st.blend = pass.blend;
    st.viewport = viewport;
    return st;
}

bool killzoneShouldShade(std::uint64_t samplesPassed, std::uint64_t threshold) {
    return samplesPassed > threshold;
}

} // namespace tessera
