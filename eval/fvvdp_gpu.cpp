#include "eval/fvvdp_gpu.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "fvvdp_band_spv.h"
#include "fvvdp_display_spv.h"
#include "fvvdp_reduce_spv.h"
#include "fvvdp_temporal_spv.h"
#include "shaders/fvvdp_params.h"

namespace wrsfov::eval::fvvdp {

namespace {

Error error(FvvdpError code, std::string message) { return Error{int(code), "fvvdp: " + std::move(message)}; }

std::string sizeText(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }


uint32_t groups(uint32_t n) { return (n + FVVDP_GROUP - 1) / FVVDP_GROUP; }

enum Binding : uint32_t { kParams, kInput, kWindow, kPyramid, kTables, kPartial, kBindings };
enum Pass : int { kDisplay, kTemporal, kReduce, kBand, kPasses };

}  // namespace

struct GpuMetric::Impl {
    vk::Context& ctx;
    Options options;
    Metric layout;        // the C++ metric, never pushed: the checked options, bands and filters
    uint32_t levels = 0;  // Gaussian levels stored: bands + 1
    uint32_t quads = 0;   // groups of 4 pixels of the display and temporal passes
    std::vector<uint32_t> bandPixels, bandGroupsX, bandGroupsY;
    gpu::FvvdpParams params{};

    vk::Buffer ubo, input, window, pyramid, tables, partial;
    vk::DescriptorSetLayout setLayout;
    vk::PipelineLayout pipelineLayout;
    vk::DescriptorPool pool;
    VkDescriptorSet set = VK_NULL_HANDLE;
    vk::ShaderModule modules[kPasses];
    vk::Pipeline pipelines[kPasses];
    vk::QueryPool queries;  // kPasses + 1 timestamps around the passes; none without timestamps
    std::array<double, 4> passMs{};

    std::size_t frames = 0;
    double sumVideo = 0.0, qImage = 0.0;
    FrameQuality last;

    Impl(vk::Context& c, Options o, Metric m) : ctx(c), options(std::move(o)), layout(std::move(m)) {}
    Status init();
    void record(VkCommandBuffer cb, uint32_t slot, uint32_t frameCount);
};

Status GpuMetric::Impl::init() {
    const ViewGeometry& g = options.geometry;
    const Parameters& p = kParameters;
    const uint32_t w = g.width, h = g.height;
    const uint64_t npix = uint64_t(w) * h;
    const int nb = int(layout.bandFrequencies().size());
    levels = uint32_t(nb) + 1;
    if (levels > FVVDP_MAX_LEVELS)
        return error(FvvdpError::InvalidOptions, "geometry " + sizeText(int(w), int(h)) + " needs " +
                                                     std::to_string(levels) + " pyramid levels, the GPU passes hold " +
                                                     std::to_string(FVVDP_MAX_LEVELS));

    // The parameter block: everything but the gaze is fixed for the metric's life.
    const int n = layout.filterLength();
    quads = uint32_t((npix + 3) / 4);
    params.image = glm::uvec4(w, h, uint32_t(n), quads);
    const double black = options.photometry.black();
    params.display = glm::vec4(float(options.photometry.peak), float(black),
                               float(std::pow(10.0, p.sensitivity_correction / 20.0)), 0.0f);
    params.fov_tan = g.fov_tan;
    params.gaze = glm::vec4(0.0f, 0.0f, float(g.ppdCentre()), 0.0f);
    params.mask =
        glm::vec4(float(p.mask_p), float(std::pow(10.0, p.mask_c)), float(p.mask_q_sust), float(p.mask_q_trans));
    params.pool = glm::vec4(float(p.beta), 0.0f, 0.0f, 0.0f);
    params.csf_axes = glm::vec4(float(std::log2(detail::kCsfYMin)), float(std::log2(detail::kCsfYMax)),
                                float(std::log2(detail::kCsfRhoMin)), float(std::log2(detail::kCsfRhoMax)));
    params.csf_ecc = glm::vec4(float(std::sqrt(detail::kCsfEccMax)), 0.0f, 0.0f, 0.0f);
    uint32_t lw = w, lh = h, texel = 0, partialAt = 0;
    for (uint32_t l = 0; l < levels; ++l) {
        params.level[l] = glm::uvec4(lw, lh, texel, partialAt);
        texel += lw * lh;
        if (int(l) < nb) {
            params.band[l] = glm::vec4(float(layout.bandFrequencies()[l]), l == 0 ? 1.0f : 2.0f, 0.0f, 0.0f);
            bandPixels.push_back(lw * lh);
            bandGroupsX.push_back(groups(lw));
            bandGroupsY.push_back(groups(lh));
            partialAt += 2 * groups(lw) * groups(lh);
        }
        lw = (lw + 1) / 2;
        lh = (lh + 1) / 2;
    }

    // Buffers.
    struct Alloc {
        vk::Buffer* buffer;
        uint64_t bytes;
        VkBufferUsageFlags usage;
        bool host;
        const char* what;
    };
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    constexpr size_t kCsfNodes = size_t(FVVDP_CSF_N) * FVVDP_CSF_N * FVVDP_CSF_N;
    const uint64_t tableFloats = 2ull * kCsfNodes + 2ull * uint64_t(n);
    for (const Alloc& a :
         {Alloc{&ubo, sizeof(gpu::FvvdpParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true, "parameters"},
          Alloc{&input, 2 * uint64_t(quads) * 48, storage, true, "input images"},
          Alloc{&window, 2 * uint64_t(n) * quads * 16, storage, false, "temporal window"},
          Alloc{&pyramid, uint64_t(texel) * 16, storage, false, "pyramid"},
          Alloc{&tables, tableFloats * 4, storage, true, "CSF tables"},
          Alloc{&partial, uint64_t(std::max(partialAt, 1u)) * 4, storage, true, "band sums"}}) {
        auto r = ctx.createBuffer(a.bytes, a.usage, a.host);
        if (!r) return Error{r.error().code, "fvvdp: " + std::string(a.what) + ": " + r.error().message};
        *a.buffer = std::move(*r);
    }
    std::memcpy(ubo.mapped(), &params, sizeof(params));
    // The padding pixels of the last quad stay 0 (they are never stored in the pyramid).
    std::memset(input.mapped(), 0, input.size());
    // The tables: per node the sustained then the transient log2 S, then the two filters.
    float* t = static_cast<float*>(tables.mapped());
    for (int c = 0; c < 2; ++c) {
        const std::vector<float> table = detail::csfTable(detail::kChannelOmega[size_t(c)]);
        for (size_t i = 0; i < kCsfNodes; ++i) t[2 * i + size_t(c)] = table[i];
    }
    const auto filters = detail::temporalFilters(options.fps);
    const size_t filterAt = 2 * kCsfNodes;
    std::memcpy(t + filterAt, filters[0].data(), size_t(n) * 4);
    std::memcpy(t + filterAt + size_t(n), filters[1].data(), size_t(n) * 4);

    // One descriptor set for all passes.
    const VkDevice dev = ctx.device();
    auto binding = [](uint32_t b, VkDescriptorType type) {
        return VkDescriptorSetLayoutBinding{b, type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    };
    auto madeSetLayout = ctx.createSetLayout(
        {binding(kParams, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER), binding(kInput, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),
         binding(kWindow, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER), binding(kPyramid, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),
         binding(kTables, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER), binding(kPartial, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER)});
    if (!madeSetLayout) return madeSetLayout.error();
    setLayout = std::move(*madeSetLayout);
    auto madePipelineLayout =
        ctx.createPipelineLayout(setLayout.get(), sizeof(gpu::FvvdpPush), VK_SHADER_STAGE_COMPUTE_BIT);
    if (!madePipelineLayout) return madePipelineLayout.error();
    pipelineLayout = std::move(*madePipelineLayout);
    const VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1},
                                           {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kBindings - 1}};
    VkDescriptorPoolCreateInfo dpci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpci.maxSets = 1;
    dpci.poolSizeCount = 2;
    dpci.pPoolSizes = sizes;
    VkDescriptorPool dp;
    VK_CHECK(vkCreateDescriptorPool(dev, &dpci, nullptr, &dp));
    pool = vk::DescriptorPool(dev, dp);
    const VkDescriptorSetLayout sl = setLayout.get();
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = dp;
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &sl;
    VK_CHECK(vkAllocateDescriptorSets(dev, &ai, &set));
    const vk::Buffer* bound[kBindings] = {&ubo, &input, &window, &pyramid, &tables, &partial};
    VkDescriptorBufferInfo infos[kBindings];
    VkWriteDescriptorSet writes[kBindings];
    for (uint32_t b = 0; b < kBindings; ++b) {
        infos[b] = {bound[b]->handle(), 0, VK_WHOLE_SIZE};
        writes[b] = vk::bufferWrite(
            set, b, b == kParams ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &infos[b]);
    }
    vkUpdateDescriptorSets(dev, kBindings, writes, 0, nullptr);

    // Pipelines; the band pass specialised for the mode (FOVEATED, FLAT_SCREEN).
    struct Code {
        const uint32_t* words;
        size_t bytes;
    };
    const Code code[kPasses] = {{fvvdp_display_spv, sizeof(fvvdp_display_spv)},
                                {fvvdp_temporal_spv, sizeof(fvvdp_temporal_spv)},
                                {fvvdp_reduce_spv, sizeof(fvvdp_reduce_spv)},
                                {fvvdp_band_spv, sizeof(fvvdp_band_spv)}};
    const uint32_t constants[2] = {uint32_t(options.foveated), uint32_t(g.model == ViewGeometry::Model::FlatScreen)};
    const VkSpecializationMapEntry entries[2] = {{0, 0, 4}, {1, 4, 4}};
    const VkSpecializationInfo spec{2, entries, sizeof(constants), constants};
    for (int s = 0; s < kPasses; ++s) {
        auto module = ctx.createShaderModule(code[s].words, code[s].bytes);
        if (!module) return module.error();
        modules[s] = std::move(*module);
        VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        ci.stage.module = modules[s].get();
        ci.stage.pName = "main";
        ci.stage.pSpecializationInfo = s == kBand ? &spec : nullptr;
        ci.layout = pipelineLayout.get();
        VkPipeline pl;
        VK_CHECK(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &ci, nullptr, &pl));
        pipelines[s] = vk::Pipeline(dev, pl);
    }
    if (ctx.timestampPeriodNs() > 0.0) {
        VkQueryPoolCreateInfo qci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        qci.queryType = VK_QUERY_TYPE_TIMESTAMP;
        qci.queryCount = kPasses + 1;
        VkQueryPool qp;
        VK_CHECK(vkCreateQueryPool(dev, &qci, nullptr, &qp));
        queries = vk::QueryPool(dev, qp);
    }
    return Status::success();
}

void GpuMetric::Impl::record(VkCommandBuffer cb, uint32_t slot, uint32_t frameCount) {
    const VkPipelineLayout pl = pipelineLayout.get();
    auto pushAt = [&](uint32_t level) {
        const gpu::FvvdpPush push{glm::uvec4(level, slot, frameCount, 0u)};
        vkCmdPushConstants(cb, pl, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    };
    auto bind = [&](Pass pass) { vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines[pass].get()); };
    auto computeBarrier = [&] {
        vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    };
    uint32_t stamps = 0;
    auto stamp = [&] {
        if (queries) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, queries.get(), stamps++);
    };
    if (queries) vkCmdResetQueryPool(cb, queries.get(), 0, kPasses + 1);
    stamp();
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pl, 0, 1, &set, 0, nullptr);
    // The per-quad passes: groups in x, then rows of them in y (fvvdp_quad).
    const uint32_t quadGroups = (quads + FVVDP_QUAD_GROUP - 1) / FVVDP_QUAD_GROUP;
    const uint32_t qx = std::min(quadGroups, uint32_t(FVVDP_QUAD_GROUPS_X)), qy = (quadGroups + qx - 1) / qx;
    bind(kDisplay);
    pushAt(0);
    vkCmdDispatch(cb, qx, qy, 2);
    computeBarrier();
    stamp();
    bind(kTemporal);
    vkCmdDispatch(cb, qx, qy, 1);
    computeBarrier();
    stamp();
    bind(kReduce);
    for (uint32_t l = 0; l + 1 < levels; ++l) {
        pushAt(l);
        vkCmdDispatch(cb, groups(params.level[l + 1].x), groups(params.level[l + 1].y), 1);
        computeBarrier();
    }
    stamp();
    bind(kBand);
    for (uint32_t b = 0; b + 1 < levels; ++b) {
        pushAt(b);
        vkCmdDispatch(cb, bandGroupsX[b], bandGroupsY[b], 1);
    }
    computeBarrier();
    stamp();
    vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                      VK_ACCESS_HOST_READ_BIT);
}

GpuMetric::GpuMetric(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GpuMetric::GpuMetric(GpuMetric&&) noexcept = default;
GpuMetric& GpuMetric::operator=(GpuMetric&&) noexcept = default;
GpuMetric::~GpuMetric() = default;

Result<GpuMetric> GpuMetric::create(vk::Context& ctx, const Options& options) {
    if (options.distortion_map)
        return error(FvvdpError::InvalidOptions,
                     "the distortion map is not computed on the GPU; use Metric for Options::distortion_map");
    auto layout = Metric::create(options);
    if (!layout) return layout.error();
    auto impl = std::make_unique<Impl>(ctx, options, std::move(*layout));
    if (Status s = impl->init(); !s) return s.error();
    return GpuMetric(std::move(impl));
}

Status GpuMetric::push(const cv::Mat& test, const cv::Mat& reference) {
    const ViewGeometry& g = impl_->options.geometry;
    return push(test, reference, glm::vec2(float(g.width / 2), float(g.height / 2)));
}

Status GpuMetric::push(const cv::Mat& test, const cv::Mat& reference, glm::vec2 gaze_px) {
    Impl& m = *impl_;
    const ViewGeometry& g = m.options.geometry;
    if (Status s = detail::checkInputFrame(test, reference, gaze_px, g); !s) return s;

    const int w = int(g.width), h = int(g.height);
    const size_t row = size_t(w) * 3;
    float* in = static_cast<float*>(m.input.mapped());
    for (int y = 0; y < h; ++y) {
        std::memcpy(in + size_t(y) * row, test.ptr<float>(y), row * 4);
        std::memcpy(in + 12 * size_t(m.quads) + size_t(y) * row, reference.ptr<float>(y), row * 4);
    }
    // Gaze as tangents (the ray through the centre of the pixel looked at), as Metric does.
    const glm::vec4 t = g.fov_tan;
    m.params.gaze.x = float(t.x + (double(gaze_px.x) + 0.5) / w * (t.y - t.x));
    m.params.gaze.y = float(t.z - (double(gaze_px.y) + 0.5) / h * (t.z - t.w));
    std::memcpy(m.ubo.mapped(), &m.params, sizeof(m.params));

    const uint32_t slot = uint32_t(m.frames % size_t(m.layout.filterLength()));
    if (Status s = m.ctx.submitAndWait([&](VkCommandBuffer cb) { m.record(cb, slot, uint32_t(m.frames + 1)); }); !s)
        return Error{s.error().code, "fvvdp: GPU frame: " + s.error().message};

    if (m.queries) {
        uint64_t ts[kPasses + 1];
        if (vkGetQueryPoolResults(m.ctx.device(), m.queries.get(), 0, kPasses + 1, sizeof(ts), ts, sizeof(uint64_t),
                                  VK_QUERY_RESULT_64_BIT) == VK_SUCCESS)
            for (int i = 0; i < kPasses; ++i)
                m.passMs[size_t(i)] = double(ts[i + 1] - ts[i]) * m.ctx.timestampPeriodNs() * 1e-6;
    }

    // Pool: per band and channel the beta-mean of the group sums (in double), then as Metric.
    const Parameters& p = kParameters;
    const float* part = static_cast<const float*>(m.partial.mapped());
    m.last.band.assign(m.bandPixels.size(), {0.0, 0.0});
    for (size_t b = 0; b < m.bandPixels.size(); ++b) {
        const uint32_t at = m.params.level[b].w, count = m.bandGroupsX[b] * m.bandGroupsY[b];
        double sum[2] = {0.0, 0.0};
        for (uint32_t i = 0; i < count; ++i)
            for (int c = 0; c < 2; ++c) sum[c] += double(part[at + 2 * i + uint32_t(c)]);
        for (int c = 0; c < 2; ++c)
            m.last.band[b][size_t(c)] = std::pow(sum[c] / double(m.bandPixels[b]), 1.0 / p.beta);
    }
    const std::array<double, 2> q = detail::poolFrame(m.last);
    if (m.frames == 0) m.qImage = q[0];
    m.sumVideo += std::pow(q[1], p.beta_t);
    ++m.frames;
    return Status::success();
}

Result<double> GpuMetric::jod() const {
    const Impl& m = *impl_;
    if (m.frames == 0) return error(FvvdpError::NoFrames, "no frames pushed yet");
    const Parameters& p = kParameters;
    const double q = m.frames == 1 ? m.qImage : std::pow(m.sumVideo / double(m.frames), 1.0 / p.beta_t);
    return detail::jodFromQuality(q);
}

const FrameQuality& GpuMetric::lastFrame() const { return impl_->last; }
std::size_t GpuMetric::frames() const { return impl_->frames; }
const std::vector<double>& GpuMetric::bandFrequencies() const { return impl_->layout.bandFrequencies(); }
int GpuMetric::filterLength() const { return impl_->layout.filterLength(); }
const Options& GpuMetric::options() const { return impl_->options; }
std::array<double, 4> GpuMetric::passMilliseconds() const { return impl_->passMs; }

void GpuMetric::reset() {
    impl_->frames = 0;
    impl_->sumVideo = 0.0;
    impl_->qImage = 0.0;
    impl_->last = {};
}

}  // namespace wrsfov::eval::fvvdp
