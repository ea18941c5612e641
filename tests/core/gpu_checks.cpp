#include "gpu_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace wrsfov::test {

Reservoirs readReservoirs(Compositor& comp) {
    Reservoirs out;
    for (uint32_t eye = 0; eye < 2; ++eye) {
        auto r = comp.readReservoirs(eye);
        EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
        if (r.ok()) out[eye] = std::move(*r);
    }
    return out;
}

void expectSameOutputs(Compositor& a, Compositor& b, const std::string& what) {
    for (uint32_t e = 0; e < 2; ++e) {
        auto oa = a.readOutput(e), ob = b.readOutput(e);
        ASSERT_TRUE(oa.ok() && ob.ok()) << what;
        EXPECT_EQ(oa->data, ob->data) << what << ": output of eye " << e;
    }
}

void expectSameReservoirs(Compositor& a, Compositor& b, const std::string& what) {
    Reservoirs ra = readReservoirs(a), rb = readReservoirs(b);
    const uint32_t W = a.width(), tx = (W + gpu::WRS_TILE - 1) / gpu::WRS_TILE;
    for (uint32_t e = 0; e < 2; ++e) {
        // A tile that sparse retention skipped in one of the two stored nothing there (all-zero).
        auto ha = a.readTileHeld(e), hb = b.readTileHeld(e);
        ASSERT_TRUE(ha.ok() && hb.ok()) << what;
        if (ha->empty() == hb->empty()) continue;  // both sparse (the same zeros) or neither
        const std::vector<float>& held = ha->empty() ? *hb : *ha;
        for (std::size_t i = 0; i < ra[e].size(); ++i)
            if (held[(i / W / gpu::WRS_TILE) * tx + (i % W) / gpu::WRS_TILE] == 0.0f) ra[e][i] = rb[e][i] = glm::uvec4(0u);
    }
    EXPECT_EQ(ra[0], rb[0]) << what << ": reservoirs of the left eye";
    EXPECT_EQ(ra[1], rb[1]) << what << ": reservoirs of the right eye";
}

void compareWithReference(Compositor& gpu, const Reference& ref, const Reservoirs& prev, StepTally& t,
                          const std::string& what) {
    const uint32_t W = gpu.width(), H = gpu.height();
    int reported = 0;
    for (uint32_t eye = 0; eye < 2; ++eye) {
        auto out = gpu.readOutput(eye);
        ASSERT_TRUE(out.ok());
        const HostImage& cpuOut = ref.output(eye);
        ASSERT_EQ(out->data.size(), cpuOut.data.size());
        for (std::size_t i = 0; i < out->data.size(); ++i) {
            int d = std::abs(int(uint8_t(out->data[i])) - int(uint8_t(cpuOut.data[i])));
            t.maxOutputDiff = std::max(t.maxOutputDiff, d);
            if (d > 1 && reported++ < 5)
                ADD_FAILURE() << what << ": eye " << eye << " pixel " << (i / 4) % W << "," << (i / 4) / W
                              << " channel " << i % 4 << ": gpu " << int(uint8_t(out->data[i])) << " cpu "
                              << int(uint8_t(cpuOut.data[i]));
        }
        auto res = gpu.readReservoirs(eye);
        ASSERT_TRUE(res.ok());
        const auto& cpuRes = ref.reservoirs(eye);
        const auto& trace = ref.trace(eye);
        ASSERT_EQ(res->size(), std::size_t(W) * H);
        for (uint32_t i = 0; i < W * H; ++i) {
            const glm::uvec4 g = (*res)[i], c = cpuRes[i];
            const gpu::Reservoir gr = gpu::wrs_unpack(g), cr = gpu::wrs_unpack(c);
            if (gr.M != cr.M && reported++ < 5)
                ADD_FAILURE() << what << ": eye " << eye << " pixel " << i % W << "," << i / W << " M gpu " << gr.M
                              << " cpu " << cr.M;
            if (!(std::fabs(gr.w_sum - cr.w_sum) <= 1e-5f * std::max(1.0f, cr.w_sum)) && reported++ < 5)
                ADD_FAILURE() << what << ": eye " << eye << " pixel " << i % W << "," << i / W << " w_sum gpu "
                              << gr.w_sum << " cpu " << cr.w_sum;
            const Reference::Trace& tr = trace[i];
            if (!tr.hadHistory) {
                // Started anew: the candidate on both sides (colour through the output check).
                if (gr.M != 1u && reported++ < 5) ADD_FAILURE() << what << ": a reservoir without history has M " << gr.M;
                continue;
            }
            t.decisions++;
            const glm::uvec4 h = prev[eye][tr.source];
            const bool gpuKeep = g.x == h.x && g.y == h.y;
            const bool ambiguous = c.x == h.x && c.y == h.y && !tr.keep;  // candidate packs like the history
            if (gpuKeep == tr.keep || ambiguous) continue;
            t.mismatches++;
            if (std::fabs(tr.rnd - tr.threshold) < 1e-6f) {
                t.nearThreshold++;
            } else if (reported++ < 5) {
                ADD_FAILURE() << what << ": eye " << eye << " pixel " << i % W << "," << i / W
                              << ": selection differs, cpu keep=" << tr.keep << " rnd=" << tr.rnd
                              << " threshold=" << tr.threshold;
            }
        }
    }
}

Reservoirs stepBoth(Compositor& gpu, StereoApp& app, Reference& ref, uint64_t frameIndex,
                    const std::array<EyeFrame, 2>& eyes, StepTally& tally, const std::string& what) {
    Reservoirs prev;
    if (gpu.width() != 0) {
        prev = readReservoirs(gpu);
        for (uint32_t e = 0; e < 2; ++e) {
            ref.setHistory(e, prev[e], *gpu.readTileHeld(e));
            ref.setSteadyFloor(e, *gpu.readSteadyFloor(e));
        }
    }
    Status s = app.submit(frameIndex, eyes);
    EXPECT_TRUE(s.ok()) << what << ": " << s.message();
    if (!s.ok()) return prev;
    if (prev[0].empty()) {
        ref.resetHistory();
        for (uint32_t e = 0; e < 2; ++e) prev[e].assign(std::size_t(gpu.width()) * gpu.height(), glm::uvec4(0u));
    }
    ref.step(gpu.lastParams(), referenceInputs(eyes));
    compareWithReference(gpu, ref, prev, tally, what);
    return prev;
}

void expectReservoirsSane(const std::vector<glm::uvec4>& packed, const std::string& what) {
    int reported = 0;
    for (std::size_t i = 0; i < packed.size(); ++i) {
        const gpu::Reservoir r = gpu::wrs_unpack(packed[i]);
        const bool ok = gpu::wrs_finite3(r.color) && gpu::wrs_finite(r.w) && gpu::wrs_finite(r.w_sum) &&
                        gpu::wrs_finite(r.z) && r.w_sum > 0.0f && r.M >= 1u && r.w >= 0.0f && r.z >= 0.0f &&
                        r.color.x >= 0.0f && r.color.y >= 0.0f && r.color.z >= 0.0f;
        if (!ok && reported++ < 5)
            ADD_FAILURE() << what << ": reservoir " << i << " colour (" << r.color.x << "," << r.color.y << ","
                          << r.color.z << ") w " << r.w << " w_sum " << r.w_sum << " M " << r.M << " z " << r.z;
    }
}

double eccentricity(const gpu::EyeParams& ep, uint32_t x, uint32_t y, uint32_t width, uint32_t height) {
    const double tx = ep.fov_tan.x + (x + 0.5) / width * (double(ep.fov_tan.y) - ep.fov_tan.x);
    const double ty = ep.fov_tan.z - (y + 0.5) / height * (double(ep.fov_tan.z) - ep.fov_tan.w);
    glm::dvec3 ray = glm::normalize(glm::dvec3(tx, ty, -1.0));
    glm::dvec3 g = glm::normalize(glm::dvec3(ep.gaze));
    return std::acos(std::clamp(glm::dot(ray, g), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

}  // namespace wrsfov::test
