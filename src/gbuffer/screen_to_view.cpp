// ScreenToView / ClipToView of the 3dgep shaders (3dgep article §3.3.3) in binary32 with a fixed
// operation order, and the corner / centre sample points of the deferred lighting pass.
#include <tessera/gbuffer/screen_to_view.h>

namespace tessera {

glm::vec4 clipToView(const glm::vec4& posClip, const glm::mat4& inverseProjection) {
    const glm::mat4& m = inverseProjection;
    // dp4 of each row of M with the vector, summed x + y + z + w left to right.
    glm::vec4 posView;
    for (int row = 0; row < 4; ++row)
        posView[row] = m[0][row] * posClip.x + m[1][row] * posClip.y + m[2][row] * posClip.z + m[3][row] * posClip.w;
    const float w = posView.w;
    return glm::vec4(posView.x / w, posView.y / w, posView.z / w, posView.w / w);
}

glm::vec4 screenToView(const glm::vec4& posScreen, const glm::vec2& screenDimensions,
                       const glm::mat4& inverseProjection) {
    const float u = posScreen.x / screenDimensions.x, v = posScreen.y / screenDimensions.y;  // texCoord
    const float xNdc = u * 2.0f - 1.0f;
    const float yNdc = (1.0f - v) * 2.0f - 1.0f;  // window y down -> NDC y up
    return clipToView(glm::vec4(xNdc, yNdc, posScreen.z, posScreen.w), inverseProjection);
}

glm::ivec2 pixelFromSvPosition(const glm::vec2& posWindow) {
    return glm::ivec2(static_cast<int>(posWindow.x), static_cast<int>(posWindow.y));  // truncation
}

glm::vec2 samplePointWindow(std::uint32_t pxX, std::uint32_t pxY, PixelSamplePoint samplePoint) {
    const float offset = samplePoint == PixelSamplePoint::Centre ? 0.5f : 0.0f;
    return glm::vec2(static_cast<float>(pxX) + offset, static_cast<float>(pxY) + offset);
}

glm::vec4 reconstructPositionView(std::uint32_t pxX, std::uint32_t pxY, float depth,
                                  const glm::vec2& screenDimensions, const glm::mat4& inverseProjection,
                                  PixelSamplePoint samplePoint) {
    const glm::vec2 pxWindow = samplePointWindow(pxX, pxY, samplePoint);
    return screenToView(glm::vec4(pxWindow, depth, 1.0f), screenDimensions, inverseProjection);
}

} // namespace tessera
