// forward-plus-amd's ray-cast shadows (GPU Pro 4 ch. 5 §5.6.2): the "shadow-jobs" pass lists one
// job per (pixel, shadow-casting light of its tile), the "shadow-rays" pass casts one Embree
// occlusion ray per job into the per-pixel shadow mask the opaque pass reads.
#include "forward_plus_amd_detail.h"

namespace tessera::forward_plus_amd_detail {
namespace {

ShadowPixels shadowPixelsOf(const AmdState& st) {
    return ShadowPixels{st.setup->width, st.setup->height, st.depthWindow, st.normalWorld, st.worldFromClip};
}

} // namespace

// "shadow-jobs": reads the G-pass (the depth as the culling pass decoded it into st.depthWindow,
// the normal) and the opaque lists, writes "shadow.jobs" (R32_UINT, the job buffer laid out as
// the light index pool).
void createJobsPass(AmdState& st, Device& device, BufferRegistry& reg) {
    const Surface& normal = reg.get("gbuffer.normal");
    st.normalWorld.resize(std::size_t{st.setup->width} * st.setup->height);
    device.execute([&] {
        std::memcpy(st.normalWorld.data(), normal.bytes().data(), st.normalWorld.size() * sizeof(glm::vec4));
        st.shadowJobs = createShadowJobs(shadowPixelsOf(st), st.opaque, st.casters, st.options.shadowRays);
    });
    Surface& jobs = reg.create("shadow.jobs", indexListDesc(st.shadowJobs.jobs.size()));
    if (!st.shadowJobs.jobs.empty())
        std::memcpy(jobs.bytes().data(), st.shadowJobs.jobs.data(), st.shadowJobs.jobs.size() * sizeof(std::uint32_t));
}

// "shadow-rays": one Embree occlusion ray per job into "shadow.mask" (R32G32B32A32_UINT per
// pixel) and "shadow.counters" (R32_UINT x 5: jobs, occluded, backface-masked, overflow pixels,
// overflow lights).
void castRaysPass(AmdState& st, Device& device, const SceneResources& res, BufferRegistry& reg) {
    const ShadowRayScene& occluders = shadowRaySceneOf(res);
    device.execute([&] { castShadowJobs(shadowPixelsOf(st), st.opaque, st.casters, occluders, st.options.shadowRays, st.shadowJobs); });
    Surface& mask = reg.create("shadow.mask", {st.setup->width, st.setup->height, Format::R32G32B32A32_UINT, 1});
    std::memcpy(mask.bytes().data(), st.shadowJobs.mask.data(), st.shadowJobs.mask.size() * sizeof(std::uint32_t));
    const ShadowJobStats& c = st.shadowJobs.stats;
    const std::array<std::uint64_t, 5> values{c.jobs, c.occluded, c.backfaceMasked, c.overflowPixels, c.overflowLights};
    Surface& counters = reg.create("shadow.counters", {5, 1, Format::R32_UINT, 1});
    for (std::size_t i = 0; i < values.size(); ++i)
        storeUint32(counters.bytes().data(), i, std::uint32_t(std::min<std::uint64_t>(values[i], 0xFFFFFFFFu)));
    if (FrameNotes* notes = st.setup->notes) {
        const bool lit = st.options.shadowRays.overflow == ShadowOverflow::Lit;
        notes->add({"shadow-mask-overflow",
                    std::string("pixel-light pairs past the 128-slot shadow mask, which has no bit for them: ") +
                        (lit ? "lit without a shadow test" : "dropped (unlit)"),
                    c.overflowLights, 31, lit ? "--option shadowOverflow=unlit" : "--option shadowOverflow=lit", true});
    }
}

} // namespace tessera::forward_plus_amd_detail
