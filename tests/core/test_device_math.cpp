// How far this device's built-in functions, through the shared header, are from the CPU's: the
// budget the GPU-vs-CPU comparison relies on.
#include <cmath>
#include <cstdio>
#include <cstring>

#include "gpu_rig.h"
#include "math_probe_spv.h"

namespace wrsfov::test {
namespace {

class DeviceMath : public GpuTest {};

TEST_F(DeviceMath, SharedFunctionsAgreeWithCpu) {
    using namespace gpu;
    const uint32_t n = 4096;
    std::vector<glm::vec4> in(n);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), e(0.0f, 60.0f), t(-1.2f, 1.2f);
    for (auto& v : in) v = glm::vec4(u(rng), e(rng), t(rng), t(rng));
    const uint32_t F = 8;
    auto bytes = runBufferKernel(math_probe_spv, sizeof(math_probe_spv),
                                 std::as_bytes(std::span(in)), n * F * sizeof(float), n);
    std::vector<float> out(n * F);
    std::memcpy(out.data(), bytes.data(), bytes.size());
    const char* names[F] = {"srgb_to_linear", "lab_f", "exp", "eccentricity", "sample_weight", "change_lstar",
                            "change_de94", "linear_to_srgb"};
    double worst[F] = {};
    for (uint32_t i = 0; i < n; ++i) {
        glm::vec4 v = in[i];
        float cpu[F] = {wrs_srgb_to_linear(v.x),
                        wrs_lab_f(v.x),
                        std::exp(-v.y),
                        wrs_eccentricity_deg(glm::normalize(glm::vec3(v.z, v.w, -1.0f)), glm::vec3(0, 0, -1)),
                        wrs_sample_weight(v.y, 2.5f),
                        wrs_change(WRS_CHANGE_LSTAR, glm::vec3(v.x), glm::vec3(v.x * 0.9f + 0.05f)),
                        wrs_change(WRS_CHANGE_DE94, glm::vec3(v.x, v.z * 0.5f + 0.5f, 0.3f),
                                   glm::vec3(v.x * 0.9f, 0.5f, v.w * 0.5f + 0.5f)),
                        wrs_linear_to_srgb(v.x)};
        for (uint32_t f = 0; f < F; ++f) {
            // Relative for values, absolute for the change term (it enters as 1 - change).
            bool absolute = f == 5 || f == 6;
            double d = std::fabs(double(out[i * F + f]) - cpu[f]) /
                       (absolute ? 1.0 : std::max(1e-3, std::fabs(double(cpu[f]))));
            worst[f] = std::max(worst[f], d);
        }
    }
    for (uint32_t f = 0; f < F; ++f) {
        std::printf("  %-16s worst relative difference GPU vs CPU: %.3g\n", names[f], worst[f]);
        EXPECT_LT(worst[f], 2e-6) << names[f];
    }
}

}  // namespace
}  // namespace wrsfov::test
