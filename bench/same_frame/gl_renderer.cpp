// GlRenderer: tessera's forward, deferred and forward-plus frames through OpenGL 4.5 on llvmpipe,
// with the states of tessera's passes (src/techniques/*.cpp, deferred_states.h) and the llvmpipe
// peer's D3D -> GL mapping (tests/peer/gl_peer.cpp): y negated in the VS, ZERO_TO_ONE clipping,
// D3D FrontCounterClockwise = TRUE -> glFrontFace(GL_CW), D3D front/back stencil -> GL front/back.
#include "gl_renderer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include <glm/gtc/type_ptr.hpp>

#include <tessera/buffers/conversion.h>
#include <tessera/math/det_math.h>
#include <tessera/gbuffer/specular_power_packing.h>
#include <tessera/culling/tile_frustum.h>
#include <tessera/scene/phong_material.h>
#include <tessera/shading/phong_lighting.h>
#include <tessera/techniques/deferred_states.h>
#include <tessera/techniques/forward_plus.h>
#include <tessera/techniques/light_volumes.h>

#include "shaders.h"

namespace tessera::samefr {
namespace {

constexpr std::uint32_t kTileSizePx = 16;  // BLOCK_SIZE

void checkGl(const char* where) {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR)
        throw std::runtime_error(std::string("same_frame: GL error ") + std::to_string(e) + " in " + where);
}

// `defines`: "#define EMULATED_SAMPLING 0|1" (shaders.h sampleSlot).
GLuint compile(GLenum stage, const std::string& defines, const std::string& body) {
    const std::string source = std::string("#version 450 core\n") + defines + glsl::kCommon + body;
    const char* text = source.c_str();
    const GLuint shader = glCreateShader(stage);
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint length = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(std::max(length, 1)), '\0');
        glGetShaderInfoLog(shader, length, nullptr, log.data());
        glDeleteShader(shader);
        throw std::runtime_error("same_frame: shader compile failed: " + log);
    }
    return shader;
}

GLuint link(std::initializer_list<GLuint> shaders) {
    const GLuint program = glCreateProgram();
    for (GLuint s : shaders) glAttachShader(program, s);
    glLinkProgram(program);
    for (GLuint s : shaders) glDeleteShader(s);
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint length = 0;
        glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(std::max(length, 1)), '\0');
        glGetProgramInfoLog(program, length, nullptr, log.data());
        glDeleteProgram(program);
        throw std::runtime_error("same_frame: program link failed: " + log);
    }
    return program;
}

GLuint graphicsProgram(const std::string& defines, const char* vertexBody, const std::string& fragmentBody) {
    return link({compile(GL_VERTEX_SHADER, defines, vertexBody), compile(GL_FRAGMENT_SHADER, defines, fragmentBody)});
}

GLuint computeProgram(const std::string& defines, const char* body) {
    return link({compile(GL_COMPUTE_SHADER, defines, body)});
}

// The light as the shaders read it (std430, 80 bytes; shaders.h struct Light).
struct GpuLight {
    float positionView[4];
    float directionView[4];
    float color[4];
    float spotlightAngleDeg, range, intensity;
    std::uint32_t enabled, type;
    float minCos, coneRadius, pad;
};
static_assert(sizeof(GpuLight) == 80);

// The Phong material uniforms of one program (forward's PS or the G-buffer PS).
struct MaterialLocations {
    GLint clipFromObject, viewFromObject, hasTexture, texCoordSet, globalAmbient, ambientColor, emissiveColor, diffuseColor,
        specularColor, opacity, specularPower, alphaThreshold, ignoreDiffuseAlpha, alphaTest, packedSpecularPower;
    void find(GLuint program) {
        const auto at = [program](const char* name) { return glGetUniformLocation(program, name); };
        clipFromObject = at("uClipFromObject");
        viewFromObject = at("uViewFromObject");
        hasTexture = at("uHasTexture");
        texCoordSet = at("uTexCoordSet");
        globalAmbient = at("uGlobalAmbient");
        ambientColor = at("uAmbientColor");
        emissiveColor = at("uEmissiveColor");
        diffuseColor = at("uDiffuseColor");
        specularColor = at("uSpecularColor");
        opacity = at("uOpacity");
        specularPower = at("uSpecularPower");
        alphaThreshold = at("uAlphaThreshold");
        ignoreDiffuseAlpha = at("uIgnoreDiffuseAlpha");
        alphaTest = at("uAlphaTest");
        packedSpecularPower = at("uPackedSpecularPower");
    }
};

// One (instance, primitive) draw with what its passes need, in scene order.
struct DrawRecord {
    GLsizei indexCount = 0;
    std::size_t firstIndexBytes = 0;
    GLint baseVertex = 0;
    bool transparent = false, doubleSided = false, frontCounterClockwise = true;
    glm::mat4 clipFromObject{1.0f}, viewFromObject{1.0f};
    PhongMaterial material;
    std::array<GLuint, 4> textures{};        // ambient, emissive, diffuse, normal (0: not bound)
    std::array<int, 4> texCoordSet{};
    bool alphaTestForward = false, alphaTestGBuffer = false;
    float packedSpecularPower = 0.0f;
};

// One light volume draw of the deferred lighting pass.
struct VolumeDraw {
    std::uint32_t lightIndex = 0;
    glm::mat4 clipFromObject{1.0f};
    bool sphere = true;
};

GLenum frontFaceFor(bool d3dFrontCounterClockwise) { return d3dFrontCounterClockwise ? GL_CW : GL_CCW; }

// The opaque passes' culling (forward.cpp): cull back, glTF doubleSided none; the item's winding.
void applyCulling(const DrawRecord& d) {
    if (d.doubleSided) {
        glDisable(GL_CULL_FACE);
    } else {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
    }
    glFrontFace(frontFaceFor(d.frontCounterClockwise));
}

} // namespace

struct GlRenderer::Impl {
    Technique technique = Technique::Forward;
    std::uint32_t width = 0, height = 0;
    glm::uvec2 tiles{0};
    std::uint32_t listCapacity = 0;
    const ForwardPassSetup* setup = nullptr;
    std::string defines;  // prepended to every shader

    GLuint phongProgram = 0, prepassProgram = 0, gbufferProgram = 0, unmarkProgram = 0, lightingProgram = 0;
    GLuint frustumProgram = 0, cullProgram = 0, heatProgram = 0;
    MaterialLocations phongLoc{}, gbufferLoc{};
    GLint prepassClip = -1, prepassView = -1, unmarkClip = -1, lightingClip = -1, lightingIndex = -1;
    GLint phongTiled = -1, phongGridSize = -1, phongIndexCapacity = -1, phongTileSize = -1;

    GLuint sceneVao = 0, sceneVbo = 0, sceneIbo = 0;
    GLuint volumeVao = 0, volumeVbo = 0, volumeIbo = 0;
    GLsizei sphereIndexCount = 0, coneIndexCount = 0;
    GLint coneBaseVertex = 0;
    std::size_t coneFirstIndexBytes = 0;
    GLuint sampler = 0;
    std::map<const Texture2D*, GLuint> textures;
    std::vector<DrawRecord> draws;
    std::vector<VolumeDraw> volumes;

    GLuint backbuffer = 0, depthStencil = 0, depthCopy = 0, gDiffuse = 0, gSpecular = 0, gNormal = 0, heatmap = 0;
    GLuint mainFbo = 0, gbufferFbo = 0;
    GLuint lightBuffer = 0, frustumBuffer = 0, counterBuffer = 0, oIndexBuffer = 0, tIndexBuffer = 0, oGridBuffer = 0,
           tGridBuffer = 0;

    std::vector<std::pair<std::string, std::function<void()>>> passes;
    bool timerQueries = false;
    std::vector<GLuint> queries;  // GL_TIME_ELAPSED, one per pass (timerQueries only)

    void uploadScene(const SceneResources& res);
    void uploadLights(const SceneResources& res);
    void makeTargets();
    void makePrograms();
    void buildPasses();

    GLuint textureFor(const Texture2D* texture);
    void setMaterial(const MaterialLocations& loc, const DrawRecord& d, bool alphaTest) const;
    void drawItem(const DrawRecord& d) const;
    void bindDrawTextures(const DrawRecord& d) const;

    void clearTargets(bool gbufferTargets) const;
    void drawForwardPass(bool transparentPass, GLenum depthFunc, bool tiled) const;
    void drawPrepass() const;
    void drawGBuffer() const;
    void drawLights() const;
    void computeFrustums() const;
    void cullLights() const;
    void writeHeatMap() const;

    void destroy();
};

GLuint GlRenderer::Impl::textureFor(const Texture2D* texture) {
    if (texture == nullptr) return 0;
    const auto found = textures.find(texture);
    if (found != textures.end()) return found->second;
    if (texture->format() != Format::R8G8B8A8_UNORM)
        throw std::runtime_error("same_frame: texture " + texture->source() + " is not R8G8B8A8_UNORM");
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    glTextureStorage2D(id, texture->levels(), GL_RGBA8, GLsizei(texture->width(0)), GLsizei(texture->height(0)));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // tessera's own mip chain, level by level: row 0 of each level is the image's top row, and
    // GL texture row 0 is t = 0, so uv addresses the same texel in both (no flip).
    for (int level = 0; level < texture->levels(); ++level)
        glTextureSubImage2D(id, level, 0, 0, GLsizei(texture->width(level)), GLsizei(texture->height(level)), GL_RGBA,
                            GL_UNSIGNED_BYTE, texture->levelBytes(level).data());
    textures.emplace(texture, id);
    checkGl("texture upload");
    return id;
}

void GlRenderer::Impl::uploadScene(const SceneResources& res) {
    // Every primitive's vertices and indices in one buffer each; draws address them by offsets.
    std::vector<SceneVertex> vertices;
    std::vector<std::uint32_t> indices;
    std::vector<std::pair<std::size_t, std::size_t>> primitiveFirst;  // (first vertex, first index)
    for (const PrimitiveBuffer& p : res.primitives()) {
        primitiveFirst.emplace_back(vertices.size(), indices.size());
        vertices.insert(vertices.end(), p.vertices.begin(), p.vertices.end());
        if (p.indices.empty()) {
            for (std::uint32_t i = 0; i < p.vertices.size(); ++i) indices.push_back(i);
        } else {
            indices.insert(indices.end(), p.indices.begin(), p.indices.end());
        }
    }
    glCreateBuffers(1, &sceneVbo);
    glNamedBufferStorage(sceneVbo, GLsizeiptr(vertices.size() * sizeof(SceneVertex)), vertices.data(), 0);
    glCreateBuffers(1, &sceneIbo);
    glNamedBufferStorage(sceneIbo, GLsizeiptr(indices.size() * sizeof(std::uint32_t)), indices.data(), 0);
    glCreateVertexArrays(1, &sceneVao);
    glVertexArrayVertexBuffer(sceneVao, 0, sceneVbo, 0, sizeof(SceneVertex));
    glVertexArrayElementBuffer(sceneVao, sceneIbo);
    const auto attrib = [&](GLuint index, GLint size, std::size_t offset) {
        glEnableVertexArrayAttrib(sceneVao, index);
        glVertexArrayAttribFormat(sceneVao, index, size, GL_FLOAT, GL_FALSE, GLuint(offset));
        glVertexArrayAttribBinding(sceneVao, index, 0);
    };
    attrib(0, 3, offsetof(SceneVertex, posObject));
    attrib(1, 3, offsetof(SceneVertex, normalObject));
    attrib(2, 4, offsetof(SceneVertex, tangentObject));
    attrib(3, 2, offsetof(SceneVertex, uv0));
    attrib(4, 2, offsetof(SceneVertex, uv1));

    // The demo's LinearRepeatSampler: trilinear, wrap (PhongSamplerChoice::Demo).
    glCreateSamplers(1, &sampler);
    glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, GL_REPEAT);

    for (const DrawItem& item : res.drawItems()) {
        const PrimitiveBuffer& prim = res.primitives()[item.primitive];
        DrawRecord d;
        d.indexCount = GLsizei(prim.indices.empty() ? prim.vertices.size() : prim.indices.size());
        d.baseVertex = GLint(primitiveFirst[item.primitive].first);
        d.firstIndexBytes = primitiveFirst[item.primitive].second * sizeof(std::uint32_t);
        d.material = phongFromGltf(res.material(item.material));
        const PhongMaterial& m = d.material;
        if (m.specularTexture.present() || m.specularPowerTexture.present() || m.bumpTexture.present() ||
            m.opacityTexture.present())
            throw std::runtime_error("same_frame: a material uses a slot glTF materials never fill (specular, power, bump, opacity)");
        d.transparent = m.isTransparent();
        d.doubleSided = m.doubleSided;
        d.frontCounterClockwise = item.frontCounterClockwise;
        // As forward.cpp: ModelView = View * World, ModelViewProjection = Projection * ModelView.
        d.viewFromObject = setup->viewFromWorld * item.worldFromObject;
        d.clipFromObject = setup->clipFromView * d.viewFromObject;
        const TextureRef* refs[4] = {&m.ambientTexture, &m.emissiveTexture, &m.diffuseTexture, &m.normalTexture};
        for (std::size_t s = 0; s < 4; ++s) {
            const BoundTexture bound = setup->textures->bind(*refs[s]);
            d.textures[s] = bound.bound() ? textureFor(bound.texture) : 0;
            d.texCoordSet[s] = bound.texCoord;
        }
        d.alphaTestForward = (phongFeatures(m, setup->alphaTest) & kPhongAlphaTest) != 0;
        d.alphaTestGBuffer = (phongFeatures(m, true) & kPhongAlphaTest) != 0;
        d.packedSpecularPower = packSpecularPower(m.specularPower);
        draws.push_back(d);
    }
    checkGl("scene upload");
}

void GlRenderer::Impl::uploadLights(const SceneResources& res) {
    const std::vector<ViewLight<float>>& lights = setup->lightsExact;
    std::vector<GpuLight> gpu(std::max<std::size_t>(lights.size(), 1));
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const ViewLight<float>& l = lights[i];
        GpuLight& g = gpu[i];
        std::memcpy(g.positionView, glm::value_ptr(l.positionView), sizeof g.positionView);
        std::memcpy(g.directionView, glm::value_ptr(l.directionView), sizeof g.directionView);
        std::memcpy(g.color, glm::value_ptr(l.color), sizeof g.color);
        g.spotlightAngleDeg = l.spotlightAngleDeg;
        g.range = l.range;
        g.intensity = l.intensity;
        g.enabled = l.enabled ? 1u : 0u;
        g.type = std::uint32_t(l.type);
        // doSpotCone's minCos and CS_main's cone radius, with tessera's libm-free cos and tan.
        g.minCos = detCos(hlsl::radians(l.spotlightAngleDeg));
        g.coneRadius = detTan(hlsl::radians(l.spotlightAngleDeg)) * l.range;
        g.pad = 0.0f;
    }
    glCreateBuffers(1, &lightBuffer);
    glNamedBufferStorage(lightBuffer, GLsizeiptr(gpu.size() * sizeof(GpuLight)), gpu.data(), 0);

    if (technique != Technique::Deferred) return;
    // Light volumes (tessera's meshes and model matrices, default options: inscribed, glm096).
    const LightVolumes lv;
    std::vector<glm::vec3> positions = lv.sphere().positions;
    positions.insert(positions.end(), lv.cone().positions.begin(), lv.cone().positions.end());
    std::vector<std::uint32_t> indices = lv.sphere().indices;
    indices.insert(indices.end(), lv.cone().indices.begin(), lv.cone().indices.end());
    sphereIndexCount = GLsizei(lv.sphere().indices.size());
    coneIndexCount = GLsizei(lv.cone().indices.size());
    coneBaseVertex = GLint(lv.sphere().positions.size());
    coneFirstIndexBytes = lv.sphere().indices.size() * sizeof(std::uint32_t);
    glCreateBuffers(1, &volumeVbo);
    glNamedBufferStorage(volumeVbo, GLsizeiptr(positions.size() * sizeof(glm::vec3)), positions.data(), 0);
    glCreateBuffers(1, &volumeIbo);
    glNamedBufferStorage(volumeIbo, GLsizeiptr(indices.size() * sizeof(std::uint32_t)), indices.data(), 0);
    glCreateVertexArrays(1, &volumeVao);
    glVertexArrayVertexBuffer(volumeVao, 0, volumeVbo, 0, sizeof(glm::vec3));
    glVertexArrayElementBuffer(volumeVao, volumeIbo);
    glEnableVertexArrayAttrib(volumeVao, 0);
    glVertexArrayAttribFormat(volumeVao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(volumeVao, 0, 0);
    const std::vector<Light>& world = res.scene().lights;
    for (std::size_t i = 0; i < world.size(); ++i) {
        const Light& light = world[i];
        if (!light.enabled) continue;  // the demo draws no volume for a disabled light
        if (light.type == LightType::Directional || !std::isfinite(light.range))
            throw std::runtime_error("same_frame: deferred lights drawn as the far-plane quad are not implemented");
        VolumeDraw v;
        v.lightIndex = std::uint32_t(i);
        v.sphere = light.type == LightType::Point;
        const glm::mat4 viewFromObject = setup->viewFromWorld * lv.worldFromObject(light, LightVolumeOptions{});
        v.clipFromObject = setup->clipFromView * viewFromObject;
        volumes.push_back(v);
    }
    checkGl("light upload");
}

void GlRenderer::Impl::makeTargets() {
    const auto texture2d = [&](GLenum format) {
        GLuint id = 0;
        glCreateTextures(GL_TEXTURE_2D, 1, &id);
        glTextureStorage2D(id, 1, format, GLsizei(width), GLsizei(height));
        glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        return id;
    };
    backbuffer = texture2d(GL_RGBA8);
    depthStencil = texture2d(GL_DEPTH24_STENCIL8);
    glTextureParameteri(depthStencil, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
    glCreateFramebuffers(1, &mainFbo);
    glNamedFramebufferTexture(mainFbo, GL_COLOR_ATTACHMENT0, backbuffer, 0);
    glNamedFramebufferTexture(mainFbo, GL_DEPTH_STENCIL_ATTACHMENT, depthStencil, 0);
    if (glCheckNamedFramebufferStatus(mainFbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("same_frame: main framebuffer incomplete");
    if (technique == Technique::Deferred) {
        // The demo's G-buffer: RT0 the back buffer, RT1 diffuse, RT2 specular (RGBA8), RT3 normal
        // (RGBA32F), D24S8; and the depth copy the lighting PS reads.
        gDiffuse = texture2d(GL_RGBA8);
        gSpecular = texture2d(GL_RGBA8);
        gNormal = texture2d(GL_RGBA32F);
        depthCopy = texture2d(GL_DEPTH24_STENCIL8);
        glTextureParameteri(depthCopy, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
        glCreateFramebuffers(1, &gbufferFbo);
        glNamedFramebufferTexture(gbufferFbo, GL_COLOR_ATTACHMENT0, backbuffer, 0);
        glNamedFramebufferTexture(gbufferFbo, GL_COLOR_ATTACHMENT1, gDiffuse, 0);
        glNamedFramebufferTexture(gbufferFbo, GL_COLOR_ATTACHMENT2, gSpecular, 0);
        glNamedFramebufferTexture(gbufferFbo, GL_COLOR_ATTACHMENT3, gNormal, 0);
        glNamedFramebufferTexture(gbufferFbo, GL_DEPTH_STENCIL_ATTACHMENT, depthStencil, 0);
        const GLenum drawBuffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
        glNamedFramebufferDrawBuffers(gbufferFbo, 4, drawBuffers);
        if (glCheckNamedFramebufferStatus(gbufferFbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw std::runtime_error("same_frame: G-buffer framebuffer incomplete");
    }
    // Forward+ buffers: frustums, the two counters, index lists of numTiles * 200 entries
    // (3dgep demo's main.cpp), grids; bound by the passes (forward also binds them, unused).
    tiles = tileCount(glm::uvec2(width, height), kTileSizePx);
    const std::uint32_t tileTotal = tiles.x * tiles.y;
    listCapacity = tileTotal * kForwardPlusAverageLightsPerTile;
    const auto buffer = [](std::size_t bytes) {
        GLuint id = 0;
        glCreateBuffers(1, &id);
        glNamedBufferStorage(id, GLsizeiptr(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
        return id;
    };
    frustumBuffer = buffer(std::size_t(tileTotal) * 4 * sizeof(glm::vec4));
    counterBuffer = buffer(2 * sizeof(std::uint32_t));
    oIndexBuffer = buffer(std::size_t(listCapacity) * sizeof(std::uint32_t));
    tIndexBuffer = buffer(std::size_t(listCapacity) * sizeof(std::uint32_t));
    oGridBuffer = buffer(std::size_t(tileTotal) * 2 * sizeof(std::uint32_t));
    tGridBuffer = buffer(std::size_t(tileTotal) * 2 * sizeof(std::uint32_t));
    if (technique == Technique::ForwardPlus) heatmap = texture2d(GL_RGBA32F);
    checkGl("targets");
}

void GlRenderer::Impl::makePrograms() {
    const std::string phongFs = std::string(glsl::kPhongSurface) + glsl::kPhongFragment;
    phongProgram = graphicsProgram(defines, glsl::kPhongVertex, phongFs);
    phongLoc.find(phongProgram);
    phongTiled = glGetUniformLocation(phongProgram, "uTiled");
    phongGridSize = glGetUniformLocation(phongProgram, "uGridSize");
    phongIndexCapacity = glGetUniformLocation(phongProgram, "uIndexCapacity");
    phongTileSize = glGetUniformLocation(phongProgram, "uTileSizePx");
    const auto lightCount = GLuint(setup->lightsExact.size());
    glProgramUniform1ui(phongProgram, glGetUniformLocation(phongProgram, "uLightCount"), lightCount);
    glProgramUniform2ui(phongProgram, phongGridSize, tiles.x, tiles.y);
    glProgramUniform1ui(phongProgram, phongIndexCapacity, listCapacity);
    glProgramUniform1f(phongProgram, phongTileSize, float(kTileSizePx));

    const glm::mat4 inverseProjection = glm::inverse(setup->clipFromView);  // ScreenToViewParams
    const auto screenParams = [&](GLuint program) {
        glProgramUniformMatrix4fv(program, glGetUniformLocation(program, "uInverseProjection"), 1, GL_FALSE,
                                  glm::value_ptr(inverseProjection));
        glProgramUniform2f(program, glGetUniformLocation(program, "uScreenDimensions"), float(width), float(height));
    };

    if (technique == Technique::ForwardPlus) {
        prepassProgram = graphicsProgram(defines, glsl::kPhongVertex, glsl::kEmptyFragment);
        prepassClip = glGetUniformLocation(prepassProgram, "uClipFromObject");
        prepassView = glGetUniformLocation(prepassProgram, "uViewFromObject");
        frustumProgram = computeProgram(defines, glsl::kFrustumCompute);
        screenParams(frustumProgram);
        glProgramUniform2ui(frustumProgram, glGetUniformLocation(frustumProgram, "uTiles"), tiles.x, tiles.y);
        glProgramUniform1ui(frustumProgram, glGetUniformLocation(frustumProgram, "uBlockSizePx"), kTileSizePx);
        cullProgram = computeProgram(defines, glsl::kCullCompute);
        screenParams(cullProgram);
        glProgramUniform1ui(cullProgram, glGetUniformLocation(cullProgram, "uLightCount"), lightCount);
        glProgramUniform2ui(cullProgram, glGetUniformLocation(cullProgram, "uTiles"), tiles.x, tiles.y);
        glProgramUniform2i(cullProgram, glGetUniformLocation(cullProgram, "uScreenPx"), GLint(width), GLint(height));
        glProgramUniform1ui(cullProgram, glGetUniformLocation(cullProgram, "uCapacity"), listCapacity);
        heatProgram = computeProgram(defines, glsl::kHeatMapCompute);
        glProgramUniform2ui(heatProgram, glGetUniformLocation(heatProgram, "uTiles"), tiles.x, tiles.y);
        glProgramUniform2i(heatProgram, glGetUniformLocation(heatProgram, "uScreenPx"), GLint(width), GLint(height));
    }
    if (technique == Technique::Deferred) {
        gbufferProgram = graphicsProgram(defines, glsl::kPhongVertex, std::string(glsl::kPhongSurface) + glsl::kGBufferFragment);
        gbufferLoc.find(gbufferProgram);
        unmarkProgram = graphicsProgram(defines, glsl::kVolumeVertex, glsl::kEmptyFragment);
        unmarkClip = glGetUniformLocation(unmarkProgram, "uClipFromObject");
        lightingProgram = graphicsProgram(defines, glsl::kVolumeVertex, glsl::kDeferredLightingFragment);
        lightingClip = glGetUniformLocation(lightingProgram, "uClipFromObject");
        lightingIndex = glGetUniformLocation(lightingProgram, "uLightIndex");
        screenParams(lightingProgram);
        glProgramUniform1ui(lightingProgram, glGetUniformLocation(lightingProgram, "uLightCount"), lightCount);
        // exp2(a * 10.5) for each stored code: tessera's unpackSpecularPower of the UNORM value.
        std::array<float, 256> unpacked{};
        for (std::uint32_t code = 0; code < 256; ++code) unpacked[code] = unpackSpecularPower(convert::unormToFloat(code, 8));
        glProgramUniform1fv(lightingProgram, glGetUniformLocation(lightingProgram, "uUnpackedSpecularPower"), 256,
                            unpacked.data());
    }
    checkGl("programs");
}

void GlRenderer::Impl::setMaterial(const MaterialLocations& loc, const DrawRecord& d, bool alphaTest) const {
    const PhongMaterial& m = d.material;
    glUniformMatrix4fv(loc.clipFromObject, 1, GL_FALSE, glm::value_ptr(d.clipFromObject));
    glUniformMatrix4fv(loc.viewFromObject, 1, GL_FALSE, glm::value_ptr(d.viewFromObject));
    glUniform4i(loc.hasTexture, d.textures[0] != 0, d.textures[1] != 0, d.textures[2] != 0, d.textures[3] != 0);
    glUniform4i(loc.texCoordSet, d.texCoordSet[0], d.texCoordSet[1], d.texCoordSet[2], d.texCoordSet[3]);
    glUniform4fv(loc.globalAmbient, 1, glm::value_ptr(m.globalAmbient));
    glUniform4fv(loc.ambientColor, 1, glm::value_ptr(m.ambientColor));
    glUniform4fv(loc.emissiveColor, 1, glm::value_ptr(m.emissiveColor));
    glUniform4fv(loc.diffuseColor, 1, glm::value_ptr(m.diffuseColor));
    glUniform4fv(loc.specularColor, 1, glm::value_ptr(m.specularColor));
    glUniform1f(loc.opacity, m.opacity);
    glUniform1f(loc.specularPower, m.specularPower);
    glUniform1f(loc.alphaThreshold, m.alphaThreshold);
    glUniform1i(loc.ignoreDiffuseAlpha, m.ignoreDiffuseAlpha ? 1 : 0);
    glUniform1i(loc.alphaTest, alphaTest ? 1 : 0);
    if (loc.packedSpecularPower >= 0) glUniform1f(loc.packedSpecularPower, d.packedSpecularPower);
}

void GlRenderer::Impl::bindDrawTextures(const DrawRecord& d) const {
    for (GLuint unit = 0; unit < 4; ++unit) glBindTextureUnit(unit, d.textures[unit]);
}

void GlRenderer::Impl::drawItem(const DrawRecord& d) const {
    glDrawElementsBaseVertex(GL_TRIANGLES, d.indexCount, GL_UNSIGNED_INT, reinterpret_cast<const void*>(d.firstIndexBytes),
                             d.baseVertex);
}

// Resets every mask a clear obeys, then clears colour to the demo's clear colour, depth to 1,
// stencil to 0 (the "clear" pass of each technique).
void GlRenderer::Impl::clearTargets(bool gbufferTargets) const {
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glStencilMask(0xFF);
    glDisable(GL_SCISSOR_TEST);
    const GLuint fbo = gbufferTargets ? gbufferFbo : mainFbo;
    const int targets = gbufferTargets ? 4 : 1;
    for (int i = 0; i < targets; ++i) glClearNamedFramebufferfv(fbo, GL_COLOR, i, glm::value_ptr(kDemoClearColor));
    glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
}

// forward.cpp drawForwardPass: opaque (depth func with writes, cull back unless double sided) or
// transparent (SrcAlpha / InvSrcAlpha, no depth writes, cull none), draw items in scene order.
void GlRenderer::Impl::drawForwardPass(bool transparentPass, GLenum depthFunc, bool tiled) const {
    glBindFramebuffer(GL_FRAMEBUFFER, mainFbo);
    glViewport(0, 0, GLsizei(width), GLsizei(height));
    glUseProgram(phongProgram);
    glBindVertexArray(sceneVao);
    glUniform1i(phongTiled, tiled ? 1 : 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, lightBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, transparentPass ? tGridBuffer : oGridBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, transparentPass ? tIndexBuffer : oIndexBuffer);
    for (GLuint unit = 0; unit < 4; ++unit) glBindSampler(unit, sampler);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(depthFunc);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_DEPTH_CLAMP);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (transparentPass) {
        glDepthMask(GL_FALSE);
        glDisable(GL_CULL_FACE);
        glEnable(GL_BLEND);
        glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ZERO);
    } else {
        glDepthMask(GL_TRUE);
        glDisable(GL_BLEND);
    }
    for (const DrawRecord& d : draws) {
        if (d.transparent != transparentPass) continue;
        if (!transparentPass) applyCulling(d);
        else glFrontFace(frontFaceFor(d.frontCounterClockwise));
        setMaterial(phongLoc, d, d.alphaTestForward);
        bindDrawTextures(d);
        drawItem(d);
    }
}

// forward_plus_prepass.cpp drawDepthPrepass: opaque items, VS only, depth LESS with writes.
void GlRenderer::Impl::drawPrepass() const {
    glBindFramebuffer(GL_FRAMEBUFFER, mainFbo);
    glViewport(0, 0, GLsizei(width), GLsizei(height));
    glUseProgram(prepassProgram);
    glBindVertexArray(sceneVao);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_CLAMP);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    for (const DrawRecord& d : draws) {
        if (d.transparent) continue;
        if (d.alphaTestForward) throw std::runtime_error("same_frame: an alpha-tested depth pre-pass is not implemented");
        applyCulling(d);
        glUniformMatrix4fv(prepassClip, 1, GL_FALSE, glm::value_ptr(d.clipFromObject));
        glUniformMatrix4fv(prepassView, 1, GL_FALSE, glm::value_ptr(d.viewFromObject));
        drawItem(d);
    }
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

// deferred.cpp drawDeferredGBuffer: opaque items, PS_Geometry (alpha test on), depth LESS with
// writes, cull back (double sided: none), four targets.
void GlRenderer::Impl::drawGBuffer() const {
    glBindFramebuffer(GL_FRAMEBUFFER, gbufferFbo);
    glViewport(0, 0, GLsizei(width), GLsizei(height));
    glUseProgram(gbufferProgram);
    glBindVertexArray(sceneVao);
    for (GLuint unit = 0; unit < 4; ++unit) glBindSampler(unit, sampler);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_CLAMP);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    for (const DrawRecord& d : draws) {
        if (d.transparent) continue;
        applyCulling(d);
        setMaterial(gbufferLoc, d, d.alphaTestGBuffer);
        bindDrawTextures(d);
        drawItem(d);
    }
}

// deferred.cpp runLights (3dgep method): per enabled light, stencil cleared to 1, the unmark
// draw (front faces, depth GREATER, DECR_SAT on pass, no colour) and the shade draw (back faces,
// depth clamp, GREATER_EQUAL, stencil EQUAL 1 on back faces, ONE + ONE into the back buffer).
void GlRenderer::Impl::drawLights() const {
    glBindFramebuffer(GL_FRAMEBUFFER, mainFbo);
    glViewport(0, 0, GLsizei(width), GLsizei(height));
    glBindVertexArray(volumeVao);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, lightBuffer);
    for (GLuint unit = 0; unit < 4; ++unit) glBindSampler(unit, 0);
    glBindTextureUnit(0, depthCopy);
    glBindTextureUnit(1, gDiffuse);
    glBindTextureUnit(2, gSpecular);
    glBindTextureUnit(3, gNormal);
    glFrontFace(GL_CW);            // the volumes: D3D FrontCounterClockwise = TRUE
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glEnable(GL_STENCIL_TEST);
    glEnable(GL_CULL_FACE);
    glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ONE, GL_ONE);
    const GLint stencilClear = kDeferredStencilClear;
    for (const VolumeDraw& v : volumes) {
        const GLsizei count = v.sphere ? sphereIndexCount : coneIndexCount;
        const void* first = reinterpret_cast<const void*>(v.sphere ? std::size_t(0) : coneFirstIndexBytes);
        const GLint base = v.sphere ? 0 : coneBaseVertex;
        glStencilMask(0xFF);
        glClearNamedFramebufferiv(mainFbo, GL_STENCIL, 0, &stencilClear);
        // Unmark (kDeferredUnmarkPass).
        glUseProgram(unmarkProgram);
        glUniformMatrix4fv(unmarkClip, 1, GL_FALSE, glm::value_ptr(v.clipFromObject));
        glCullFace(GL_BACK);
        glDisable(GL_DEPTH_CLAMP);
        glDepthFunc(GL_GREATER);
        glStencilFuncSeparate(GL_FRONT, GL_ALWAYS, 1, 0xFF);
        glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_KEEP, GL_DECR);
        glStencilFuncSeparate(GL_BACK, GL_ALWAYS, 1, 0xFF);
        glStencilOpSeparate(GL_BACK, GL_KEEP, GL_KEEP, GL_KEEP);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glDisable(GL_BLEND);
        glDrawElementsBaseVertex(GL_TRIANGLES, count, GL_UNSIGNED_INT, first, base);
        // Shade (kDeferredShadePass).
        glUseProgram(lightingProgram);
        glUniformMatrix4fv(lightingClip, 1, GL_FALSE, glm::value_ptr(v.clipFromObject));
        glUniform1ui(lightingIndex, v.lightIndex);
        glCullFace(GL_FRONT);
        glEnable(GL_DEPTH_CLAMP);
        glDepthFunc(GL_GEQUAL);
        glStencilFuncSeparate(GL_FRONT, GL_ALWAYS, 1, 0xFF);
        glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_KEEP, GL_KEEP);
        glStencilFuncSeparate(GL_BACK, GL_EQUAL, 1, 0xFF);
        glStencilOpSeparate(GL_BACK, GL_KEEP, GL_KEEP, GL_KEEP);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glEnable(GL_BLEND);
        glDrawElementsBaseVertex(GL_TRIANGLES, count, GL_UNSIGNED_INT, first, base);
    }
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_DEPTH_CLAMP);
    glDisable(GL_BLEND);
    glStencilMask(0xFF);
    for (GLuint unit = 0; unit < 4; ++unit) glBindTextureUnit(unit, 0);
}

void GlRenderer::Impl::computeFrustums() const {
    glUseProgram(frustumProgram);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, frustumBuffer);
    glDispatchCompute((tiles.x + kTileSizePx - 1) / kTileSizePx, (tiles.y + kTileSizePx - 1) / kTileSizePx, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void GlRenderer::Impl::cullLights() const {
    const std::uint32_t zeros[2] = {0, 0};  // the demo resets both counters every frame
    glNamedBufferSubData(counterBuffer, 0, sizeof zeros, zeros);
    glUseProgram(cullProgram);
    glBindTextureUnit(0, depthStencil);
    glBindSampler(0, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, lightBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, frustumBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, counterBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, oIndexBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, tIndexBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, oGridBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, tGridBuffer);
    glDispatchCompute(tiles.x, tiles.y, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glBindTextureUnit(0, 0);
}

void GlRenderer::Impl::writeHeatMap() const {
    glUseProgram(heatProgram);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, oGridBuffer);
    glBindImageTexture(0, heatmap, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(tiles.x, tiles.y, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

void GlRenderer::Impl::buildPasses() {
    switch (technique) {
    case Technique::Forward:
        passes.emplace_back("clear", [this] { clearTargets(false); });
        passes.emplace_back("opaque", [this] { drawForwardPass(false, GL_LESS, false); });
        passes.emplace_back("transparent", [this] { drawForwardPass(true, GL_LESS, false); });
        break;
    case Technique::Deferred:
        passes.emplace_back("clear", [this] { clearTargets(true); });
        passes.emplace_back("gbuffer", [this] { drawGBuffer(); });
        passes.emplace_back("copy depth", [this] {
            glCopyImageSubData(depthStencil, GL_TEXTURE_2D, 0, 0, 0, 0, depthCopy, GL_TEXTURE_2D, 0, 0, 0, 0, GLsizei(width),
                               GLsizei(height), 1);
        });
        passes.emplace_back("lights", [this] { drawLights(); });
        passes.emplace_back("transparent", [this] { drawForwardPass(true, GL_LESS, false); });
        break;
    case Technique::ForwardPlus:
        passes.emplace_back("clear", [this] { clearTargets(false); });
        passes.emplace_back("depth-prepass", [this] { drawPrepass(); });
        passes.emplace_back("frustums", [this] { computeFrustums(); });
        passes.emplace_back("light-culling", [this] { cullLights(); });
        passes.emplace_back("heatmap", [this] { writeHeatMap(); });
        // Both Forward+ pipelines test LESS_EQUAL (forward_plus.cpp).
        passes.emplace_back("opaque", [this] { drawForwardPass(false, GL_LEQUAL, true); });
        passes.emplace_back("transparent", [this] { drawForwardPass(true, GL_LEQUAL, true); });
        break;
    }
}

void GlRenderer::Impl::destroy() {
    const GLuint programs[] = {phongProgram, prepassProgram, gbufferProgram, unmarkProgram,
                               lightingProgram, frustumProgram, cullProgram, heatProgram};
    for (GLuint p : programs) glDeleteProgram(p);
    const GLuint buffers[] = {sceneVbo, sceneIbo, volumeVbo, volumeIbo, lightBuffer, frustumBuffer,
                              counterBuffer, oIndexBuffer, tIndexBuffer, oGridBuffer, tGridBuffer};
    glDeleteBuffers(GLsizei(std::size(buffers)), buffers);
    const GLuint vaos[] = {sceneVao, volumeVao};
    glDeleteVertexArrays(2, vaos);
    glDeleteSamplers(1, &sampler);
    for (const auto& [texture, id] : textures) glDeleteTextures(1, &id);
    const GLuint targets[] = {backbuffer, depthStencil, depthCopy, gDiffuse, gSpecular, gNormal, heatmap};
    glDeleteTextures(GLsizei(std::size(targets)), targets);
    const GLuint fbos[] = {mainFbo, gbufferFbo};
    glDeleteFramebuffers(2, fbos);
    if (!queries.empty()) glDeleteQueries(GLsizei(queries.size()), queries.data());
}

GlRenderer::GlRenderer(const SceneResources& resources, const ForwardPassSetup& setup, Technique technique,
                       const GlOptions& options)
    : mImpl(std::make_unique<Impl>()) {
    mImpl->defines = std::string("#define EMULATED_SAMPLING ") + (options.emulatedSampling ? "1" : "0") + "\n";
    Impl& im = *mImpl;
    im.technique = technique;
    im.timerQueries = options.timerQueries;
    im.setup = &setup;
    im.width = setup.width;
    im.height = setup.height;
    // Frame-independent state: D3D clip volume and depth range (gl_peer.cpp), no dithering.
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthRange(0.0, 1.0);
    glDisable(GL_DITHER);
    glDisable(GL_MULTISAMPLE);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_FRAMEBUFFER_SRGB);
    im.makeTargets();
    im.uploadScene(resources);
    im.uploadLights(resources);
    im.makePrograms();
    im.buildPasses();
    if (im.timerQueries) {
        im.queries.resize(im.passes.size());
        glCreateQueries(GL_TIME_ELAPSED, GLsizei(im.queries.size()), im.queries.data());
    }
    glFinish();
    checkGl("setup");
}

GlRenderer::~GlRenderer() { mImpl->destroy(); }

std::vector<PassTime> GlRenderer::renderFrame() {
    Impl& im = *mImpl;
    std::vector<PassTime> times;
    glFinish();
    for (std::size_t i = 0; i < im.passes.size(); ++i) {
        const auto& [name, run] = im.passes[i];
        const auto t0 = std::chrono::steady_clock::now();
        if (im.timerQueries) glBeginQuery(GL_TIME_ELAPSED, im.queries[i]);
        run();
        if (im.timerQueries) glEndQuery(GL_TIME_ELAPSED);
        glFinish();
        const auto t1 = std::chrono::steady_clock::now();
        times.push_back({name, std::chrono::duration<double, std::milli>(t1 - t0).count()});
    }
    if (im.timerQueries)  // every pass has finished: the results are available without a stall
        for (std::size_t i = 0; i < im.passes.size(); ++i) {
            GLuint64 ns = 0;
            glGetQueryObjectui64v(im.queries[i], GL_QUERY_RESULT, &ns);
            times[i].gpuMilliseconds = double(ns) * 1e-6;
        }
    checkGl("frame");
    return times;
}

GlImages GlRenderer::readBack() const {
    const Impl& im = *mImpl;
    GlImages out;
    const std::size_t pixels = std::size_t(im.width) * im.height;
    out.rgba8.resize(pixels * 4);
    out.depthStencil.resize(pixels);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, im.mainFbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    // GL memory row r == D3D row r (the VS negates y): read without flipping.
    glReadPixels(0, 0, GLsizei(im.width), GLsizei(im.height), GL_RGBA, GL_UNSIGNED_BYTE, out.rgba8.data());
    glReadPixels(0, 0, GLsizei(im.width), GLsizei(im.height), GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8, out.depthStencil.data());
    checkGl("read-back");
    return out;
}

GlLightLists GlRenderer::readLightLists() const {
    const Impl& im = *mImpl;
    GlLightLists lists;
    if (im.technique != Technique::ForwardPlus) return lists;
    const std::size_t tileTotal = std::size_t(im.tiles.x) * im.tiles.y;
    const auto read = [](GLuint buffer, std::size_t count) {
        std::vector<std::uint32_t> v(count);
        glGetNamedBufferSubData(buffer, 0, GLsizeiptr(count * sizeof(std::uint32_t)), v.data());
        return v;
    };
    lists.opaqueGrid = read(im.oGridBuffer, tileTotal * 2);
    lists.transparentGrid = read(im.tGridBuffer, tileTotal * 2);
    lists.opaqueIndex = read(im.oIndexBuffer, im.listCapacity);
    lists.transparentIndex = read(im.tIndexBuffer, im.listCapacity);
    checkGl("light list read-back");
    return lists;
}

} // namespace tessera::samefr
