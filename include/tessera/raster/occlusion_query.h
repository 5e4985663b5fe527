// D3D11_QUERY_OCCLUSION: counts the samples that pass the depth and stencil tests and are
// not discarded, between begin() and end(), over every draw that is given the query.
#pragma once

#include <cstdint>

namespace tessera {

class OcclusionQuery {
public:
    void begin() { mSamplesPassed = 0; mActive = true; }
    void end() { mActive = false; }
    bool active() const { return mActive; }
    std::uint64_t samplesPassed() const { return mSamplesPassed; }
    void add(std::uint64_t samples) { mSamplesPassed += samples; }  // called once per draw, after it

private:
    std::uint64_t mSamplesPassed = 0;
    bool mActive = false;
};

} // namespace tessera
