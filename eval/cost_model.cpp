#include "eval/cost_model.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "classify_spv.h"
#include "compositor/compose.h"
#include "compose_spv.h"
#include "foveate_spv.h"
#include "pyramid_spv.h"
#include "retain_spv.h"
#include "shaders/config.h"
#include "shaders/wrs_common.h"
#include "shaders/wrs_params.h"
#include "taa_spv.h"
#include "wrs_spv.h"

extern char** environ;

namespace wrsfov::eval {

std::span<const uint32_t> spirv(ShaderId s) {
    switch (s) {
        case ShaderId::Classify:
            return classify_spv;
        case ShaderId::Pyramid:
            return pyramid_spv;
        case ShaderId::Foveate:
            return foveate_spv;
        case ShaderId::Wrs:
            return wrs_spv;
        case ShaderId::Taa:
            return taa_spv;
        case ShaderId::Retain:
            return retain_spv;
        case ShaderId::Compose:
            return compose_spv;
    }
    return {};
}

std::string tileClassName(int tileClass) {
    switch (tileClass) {
        case kWholeImage:
            return "whole";
        case kInsetGroups:
            return "inset";
        case kOutsideInset:
            return "outside";
        case int(gpu::WRS_TILE_ANY):
            return "any";
        case int(gpu::WRS_TILE_FOVEA):
            return "fovea";
        case int(gpu::WRS_TILE_MID):
            return "mid";
        case int(gpu::WRS_TILE_SKIP):
            return "skip";
        case int(gpu::WRS_TILE_FAR):
            return "far";
    }
    return "?";
}

namespace {

uint64_t groupsOf(uint64_t n, uint64_t size) { return (n + size - 1) / size; }

}  // namespace

std::vector<PipelineVariant> pipelineVariants(const CompositorConfig& c, const TrafficInputs& in, uint32_t eyes) {
    std::vector<PipelineVariant> v;
    // A phase: the dispatches recorded with no barrier between them. `gauss` builds its pyramid in one
    // dispatch per level with barriers between, of which the classification before it overlaps only the
    // first: the model keeps them apart.
    int phase = 0;
    bool open = false;  // the last dispatch was followed by no barrier
    for (const PassDispatch& d : framePasses(c, in)) {
        if (d.shape == DispatchShape::GaussLevels && open) ++phase;
        PipelineVariant x;
        x.pass = std::string(toString(d.pass));
        x.shader = d.shader;
        std::copy(d.constants.begin(), d.constants.end(), x.constants.begin());
        // Constant 7 (HARDWARE_HALF) of every pass but compose: the device's fp16 conversion, which the
        // compositor uses where its probe finds round to nearest even, as AMD's v_cvt_f16_f32 does in the
        // default mode (the null device runs nothing, so the probe cannot run there). Constant 8
        // (TRACK_BIRTH): the stale-pixel evaluation's birth colours, where the configuration tracks them.
        if (d.shader != ShaderId::Compose) {
            x.constants[7] = 1;
            x.constants[8] = c.trackBirth ? 1u : 0u;
        }
        x.tileClass = d.shape == DispatchShape::TileList      ? d.tileClass
                      : d.shape == DispatchShape::InsetGroups  ? kInsetGroups
                      : d.shape == DispatchShape::OutsideInset ? kOutsideInset
                                                               : kWholeImage;
        x.groups = d.shape == DispatchShape::TileList ? 0 : dispatchGroups(d, in.width, in.height, eyes);
        x.invocationsPerGroup = WRS_GROUP_X * WRS_GROUP_Y;
        x.bytesPerPx = d.read + d.write;
        if (d.shape == DispatchShape::InsetGroups || d.shape == DispatchShape::OutsideInset) x.cover = d.cover;
        x.phase = phase;
        v.push_back(x);
        open = d.after == Barrier::None;
        if (!open) ++phase;
    }
    return v;
}

std::string toString(const VariantKey& k) {
    std::string s(toString(k.shader));
    for (std::size_t i = 0; i < k.constants.size(); ++i) s += (i ? "," : ":") + std::to_string(k.constants[i]);
    return s;
}

std::optional<VariantKey> parseVariantKey(std::string_view text) {
    const auto colon = text.find(':');
    if (colon == std::string_view::npos) return std::nullopt;
    VariantKey k;
    bool found = false;
    for (ShaderId s : {ShaderId::Classify, ShaderId::Pyramid, ShaderId::Foveate, ShaderId::Wrs, ShaderId::Taa,
                       ShaderId::Retain, ShaderId::Compose})
        if (toString(s) == text.substr(0, colon)) k.shader = s, found = true;
    if (!found) return std::nullopt;
    std::string_view rest = text.substr(colon + 1);
    for (std::size_t i = 0; i < k.constants.size(); ++i) {
        const auto comma = rest.find(',');
        const std::string_view num = rest.substr(0, comma);
        auto [end, ec] = std::from_chars(num.data(), num.data() + num.size(), k.constants[i]);
        if (ec != std::errc{} || end != num.data() + num.size()) return std::nullopt;
        if ((comma == std::string_view::npos) != (i + 1 == k.constants.size())) return std::nullopt;
        rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    }
    return k;
}

Result<ExecutableStats> parseStatistics(std::span<const VkPipelineExecutableStatisticKHR> stats,
                                        uint32_t subgroupSize) {
    auto value = [](const VkPipelineExecutableStatisticKHR& s) -> double {
        switch (s.format) {
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR:
                return s.value.b32 ? 1.0 : 0.0;
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR:
                return double(s.value.i64);
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR:
                return double(s.value.u64);
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR:
                return s.value.f64;
            default:
                return std::numeric_limits<double>::quiet_NaN();
        }
    };
    ExecutableStats out;
    out.subgroupSize = subgroupSize;
    struct Field {
        const char* name;
        double ExecutableStats::*member;
        bool required;
    };
    const Field fields[] = {{"Instructions", &ExecutableStats::instructions, true},
                            {"VGPRs", &ExecutableStats::vgprs, true},
                            {"SGPRs", &ExecutableStats::sgprs, true},
                            {"Subgroups per SIMD", &ExecutableStats::wavesPerSimd, true},
                            {"Latency", &ExecutableStats::latency, true},
                            {"Inverse Throughput", &ExecutableStats::invThroughput, true},
                            {"Spilled VGPRs", &ExecutableStats::spilledVgprs, false},
                            {"Spilled SGPRs", &ExecutableStats::spilledSgprs, false}};
    std::string missing;
    for (const Field& f : fields) {
        auto it = std::find_if(stats.begin(), stats.end(), [&](const VkPipelineExecutableStatisticKHR& s) {
            return std::strcmp(s.name, f.name) == 0;
        });
        if (it != stats.end() && std::isfinite(value(*it))) {
            out.*f.member = value(*it);
        } else if (f.required) {
            missing += (missing.empty() ? "" : ", ") + std::string("\"") + f.name + "\"";
        }
    }
    if (!missing.empty())
        return Error{int(CostError::Unavailable),
                     "the driver's pipeline statistics lack " + missing +
                         " (the model reads the statistics of Mesa's ACO compiler, which RADV reports)"};
    if (subgroupSize == 0) return Error{int(CostError::Unavailable), "the executable reports no subgroup size"};
    return out;
}

std::span<const GpuFigures> gpuTable() {
    static const GpuFigures table[] = {
        {"gfx1100", "AMD Radeon RX 7900 XTX (RDNA 3, Navi 31)", "7900 XTX", 96, 192, 2300.0, 960.0, 2048, 2048,
         "AMD's product page for the RX 7900 XTX (amd.com, specifications): 96 compute units, game clock "
         "2300 MHz (boost up to 2500), 384-bit GDDR6 at 20 Gbps, 960 GB/s; 2 SIMD32 per compute unit "
         "(AMD RDNA 3 instruction set architecture guide)"},
        {"vangogh", "Valve Steam Deck APU (RDNA 2, Van Gogh)", "VANGOGH", 8, 16, 1600.0, 88.0, 1832, 1920,
         "Valve's Steam Deck tech specs (steamdeck.com/en/tech): 8 RDNA 2 compute units at 1.0-1.6 GHz, 16 GB "
         "LPDDR5 at 5500 MT/s on a quad 32-bit bus, 88 GB/s, shared with the CPU; 2 SIMD32 per compute unit "
         "(AMD RDNA 2 instruction set architecture guide)"},
    };
    return table;
}

const GpuFigures* findGpu(std::string_view name) {
    for (const GpuFigures& g : gpuTable())
        if (g.name == name) return &g;
    return nullptr;
}

Result<StatsTarget> parseStatsTarget(std::string_view text) {
    StatsTarget t;
    if (text.starts_with("device:")) {
        t.deviceName = std::string(text.substr(7));
        if (t.deviceName.empty()) return Error{1, "device: needs part of a device name, e.g. device:7900"};
        return t;
    }
    if (text.empty() || text.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string_view::npos)
        return Error{1, "'" + std::string(text) + "' is neither a RADV family (gfx1100, vangogh, ...) nor device:NAME"};
    t.family = std::string(text);
    return t;
}

namespace {

// Where Mesa installs RADV's loader manifest.
std::string radvIcd() {
    for (const char* dir : {"/usr/share/vulkan/icd.d", "/usr/local/share/vulkan/icd.d", "/etc/vulkan/icd.d"}) {
        std::error_code ec;
        for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
            const std::string name = e.path().filename().string();
            if (name.starts_with("radeon_icd") && name.ends_with(".json")) return e.path().string();
        }
    }
    return "";
}

Error unavailable(std::string m) { return Error{int(CostError::Unavailable), std::move(m)}; }
Error failed(std::string m) { return Error{int(CostError::Failed), std::move(m)}; }

}  // namespace

static Result<std::map<VariantKey, ExecutableStats>> collectStatisticsOnce(const std::string& exe,
                                                                           const StatsTarget& target,
                                                                           const std::vector<VariantKey>& keys) {
    // The child's environment: this process's, with the null device's variables where asked.
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e) {
        const std::string_view kv(*e);
        if (!target.family.empty() && (kv.starts_with("VK_ICD_FILENAMES=") || kv.starts_with("VK_DRIVER_FILES=") ||
                                       kv.starts_with("RADV_FORCE_FAMILY=")))
            continue;
        env.emplace_back(kv);
    }
    if (!target.family.empty()) {
        const std::string icd = radvIcd();
        if (icd.empty())
            return unavailable(
                "no RADV loader manifest (radeon_icd.*.json in /usr/share/vulkan/icd.d): Mesa's RADV "
                "driver, whose null device gives the statistics for " +
                target.family + ", is not installed (Debian: mesa-vulkan-drivers)");
        env.push_back("VK_ICD_FILENAMES=" + icd);
        env.push_back("VK_DRIVER_FILES=" + icd);
        env.push_back("RADV_FORCE_FAMILY=" + target.family);
    }
    std::vector<std::string> args{exe, "--cost-model-child", target.label()};
    for (const VariantKey& k : keys) args.push_back(toString(k));
    std::vector<char*> argv, envp;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    for (std::string& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);

    int fds[2];
    if (pipe(fds) != 0) return failed(std::string("pipe: ") + std::strerror(errno));
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid < 0) return failed(std::string("fork: ") + std::strerror(errno));
    if (pid == 0) {
        dup2(fds[1], STDOUT_FILENO);
        dup2(fds[1], STDERR_FILENO);  // the driver's own complaints ("radv: Unknown family") come with the reason
        close(fds[0]);
        close(fds[1]);
        execve(exe.c_str(), argv.data(), envp.data());
        _exit(127);
    }
    close(fds[1]);
    std::string out;
    char buf[4096];
    for (ssize_t n; (n = read(fds[0], buf, sizeof(buf))) != 0;) {
        if (n < 0) {
            if (errno == EINTR) continue;
            break;
        }
        out.append(buf, std::size_t(n));
    }
    close(fds[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }

    // The child's lines: "executable KEY SUBGROUP", "stat NAME\tFORMAT\tVALUE", "skip: ...", "error: ...".
    std::map<VariantKey, std::vector<VkPipelineExecutableStatisticKHR>> raw;
    std::map<VariantKey, uint32_t> subgroups;
    std::string messages;
    std::optional<VariantKey> current;
    bool deviceFound = false;
    std::istringstream lines(out);
    for (std::string line; std::getline(lines, line);) {
        if (line.starts_with("executable\t")) {
            std::istringstream f(line.substr(11));
            std::string key;
            uint32_t sg = 0;
            f >> key >> sg;
            current = parseVariantKey(key);
            if (current) subgroups[*current] = sg;
        } else if (line.starts_with("stat\t") && current) {
            const auto a = line.find('\t', 5), b = line.find('\t', a + 1);
            if (a == std::string::npos || b == std::string::npos) continue;
            VkPipelineExecutableStatisticKHR s{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR};
            std::snprintf(s.name, sizeof(s.name), "%s", line.substr(5, a - 5).c_str());
            s.format = VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR;
            s.value.f64 = std::strtod(line.c_str() + b + 1, nullptr);
            raw[*current].push_back(s);
        } else if (line.starts_with("device\t")) {
            deviceFound = true;
        } else if (!line.empty()) {
            messages += (messages.empty() ? "" : "; ") + (line.starts_with("skip: ") ? line.substr(6) : line);
        }
    }
    const std::string who =
        target.family.empty() ? "device '" + target.deviceName + "'" : "RADV's null device for " + target.family;
    // RADV aborts on a family it does not know (Mesa 22.3: "radv: Unknown family") before it offers a
    // device: that is a missing null device, not a failure of the model.
    if (WIFSIGNALED(status) && !deviceFound && !target.family.empty())
        return unavailable(who + ": RADV stopped (signal " + std::to_string(WTERMSIG(status)) +
                           ") before offering a device" + (messages.empty() ? "" : " (" + messages + ")") +
                           ": this Mesa's RADV has no null device for that family");
    if (WIFSIGNALED(status))
        return Error{int(CostError::Crashed), who + ": the statistics process died of signal " +
                                                  std::to_string(WTERMSIG(status)) +
                                                  (messages.empty() ? "" : " (" + messages + ")")};
    const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (rc == 2) return unavailable(who + ": " + (messages.empty() ? "unavailable" : messages));
    if (rc == 127) return failed("cannot run " + exe + " for the statistics");
    if (rc != 0) return failed(who + ": " + (messages.empty() ? "exit code " + std::to_string(rc) : messages));
    std::map<VariantKey, ExecutableStats> result;
    for (const VariantKey& k : keys) {
        auto it = raw.find(k);
        if (it == raw.end()) return failed(who + ": no statistics for " + toString(k));
        auto s = parseStatistics(it->second, subgroups[k]);
        if (!s) return Error{s.error().code, who + ": " + s.error().message};
        result[k] = *s;
    }
    return result;
}

Result<std::map<VariantKey, ExecutableStats>> collectStatistics(const std::string& exe, const StatsTarget& target,
                                                                const std::vector<VariantKey>& keys) {
    auto r = collectStatisticsOnce(exe, target, keys);
    if (r || r.error().code != int(CostError::Crashed)) return r;
    std::fprintf(stderr, "wrsfov-bench: cost model: %s; trying once more\n", r.error().message.c_str());
    r = collectStatisticsOnce(exe, target, keys);
    if (!r && r.error().code == int(CostError::Crashed))
        return Error{r.error().code, r.error().message + " (twice)"};
    return r;
}

namespace {

// The child's Vulkan objects, destroyed in reverse order on every path.
struct StatsDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkDescriptorSetLayout composeSetLayout = VK_NULL_HANDLE;
    VkPipelineLayout composeLayout = VK_NULL_HANDLE;
    ~StatsDevice() {
        if (device) {
            if (composeLayout) vkDestroyPipelineLayout(device, composeLayout, nullptr);
            if (composeSetLayout) vkDestroyDescriptorSetLayout(device, composeSetLayout, nullptr);
            if (layout) vkDestroyPipelineLayout(device, layout, nullptr);
            if (setLayout) vkDestroyDescriptorSetLayout(device, setLayout, nullptr);
            vkDestroyDevice(device, nullptr);
        }
        if (messenger) {
            auto fn = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            if (fn) fn(instance, messenger, nullptr);
        }
        if (instance) vkDestroyInstance(instance, nullptr);
    }
};

int validationMessages = 0;

VKAPI_ATTR VkBool32 VKAPI_CALL onValidation(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                            VkDebugUtilsMessageTypeFlagsEXT,
                                            const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
    if (severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)) {
        ++validationMessages;
        std::printf("validation: %s\n", data->pMessage ? data->pMessage : "");
    }
    return VK_FALSE;
}

bool hasInstanceLayer(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    return std::any_of(layers.begin(), layers.end(),
                       [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

}  // namespace

int statisticsChildMain(std::string_view targetText, const std::vector<std::string>& keyTexts) {
    auto skip = [](const std::string& m) {
        std::printf("skip: %s\n", m.c_str());
        return 2;
    };
    auto fail = [](const std::string& m) {
        std::printf("error: %s\n", m.c_str());
        return 1;
    };
    auto target = parseStatsTarget(targetText);
    if (!target) return fail(target.error().message);
    std::vector<VariantKey> keys;
    for (const std::string& t : keyTexts) {
        auto k = parseVariantKey(t);
        if (!k) return fail("not a pipeline variant: " + t);
        keys.push_back(*k);
    }
    const char* v = std::getenv("WRSFOV_VALIDATION");
    const bool validation = v && *v && std::strcmp(v, "0") != 0;

    StatsDevice d;
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "wrsfov-cost-model";
    app.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    const char* layer = "VK_LAYER_KHRONOS_validation";
    const char* debugExt = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    VkDebugUtilsMessengerCreateInfoEXT dbg{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    dbg.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    dbg.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    dbg.pfnUserCallback = &onValidation;
    if (validation) {
        if (!hasInstanceLayer(layer))
            return fail("validation was requested but VK_LAYER_KHRONOS_validation is not installed");
        ici.enabledLayerCount = 1;
        ici.ppEnabledLayerNames = &layer;
        ici.enabledExtensionCount = 1;
        ici.ppEnabledExtensionNames = &debugExt;
        ici.pNext = &dbg;
    }
    if (VkResult r = vkCreateInstance(&ici, nullptr, &d.instance); r != VK_SUCCESS) {
        d.instance = VK_NULL_HANDLE;
        return skip("no Vulkan instance (" + std::string(vk::resultString(r)) + ")" +
                    (target->family.empty() ? "" : ": RADV found no null device for " + target->family));
    }
    if (validation) {
        auto fn = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(d.instance, "vkCreateDebugUtilsMessengerEXT"));
        if (fn) fn(d.instance, &dbg, nullptr, &d.messenger);
    }
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(d.instance, &n, nullptr);
    std::vector<VkPhysicalDevice> devices(n);
    vkEnumeratePhysicalDevices(d.instance, &n, devices.data());
    VkPhysicalDevice chosen = VK_NULL_HANDLE;
    std::string names;
    for (VkPhysicalDevice p : devices) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(p, &props);
        const std::string name = props.deviceName;
        names += (names.empty() ? "" : ", ") + name;
        std::string upper = target->family;
        std::transform(upper.begin(), upper.end(), upper.begin(),
                       [](unsigned char c) { return char(std::toupper(c)); });
        const bool match = target->family.empty()
                               ? name.find(target->deviceName) != std::string::npos
                               : name.find("RADV") != std::string::npos && name.find(upper) != std::string::npos;
        if (match && !chosen) chosen = p;
    }
    if (!chosen)
        return skip(target->family.empty()
                        ? "no Vulkan device's name contains '" + target->deviceName +
                              "' (devices: " + (names.empty() ? "none" : names) + ")"
                        : "RADV_FORCE_FAMILY=" + target->family +
                              " gave no RADV null device (devices: " + (names.empty() ? "none" : names) +
                              "); this Mesa's RADV may not know the family or have no null device");
    std::printf("device\t%s\n", names.c_str());
    uint32_t extCount = 0;
    vkEnumerateDeviceExtensionProperties(chosen, nullptr, &extCount, nullptr);
    std::vector<VkExtensionProperties> exts(extCount);
    vkEnumerateDeviceExtensionProperties(chosen, nullptr, &extCount, exts.data());
    if (std::none_of(exts.begin(), exts.end(), [](const VkExtensionProperties& e) {
            return std::strcmp(e.extensionName, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME) == 0;
        }))
        return skip("the device has no " + std::string(VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME) +
                    ": no compiler statistics");
    VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR feature{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f2.pNext = &feature;
    vkGetPhysicalDeviceFeatures2(chosen, &f2);
    if (!feature.pipelineExecutableInfo) return skip("the device does not offer pipelineExecutableInfo");
    uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(chosen, &qn, nullptr);
    std::vector<VkQueueFamilyProperties> qf(qn);
    vkGetPhysicalDeviceQueueFamilyProperties(chosen, &qn, qf.data());
    uint32_t family = 0;
    while (family < qn && !(qf[family].queueFlags & VK_QUEUE_COMPUTE_BIT)) ++family;
    if (family == qn) return skip("the device has no compute queue");
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    q.queueFamilyIndex = family;
    q.queueCount = 1;
    q.pQueuePriorities = &priority;
    const char* ext = VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.pNext = &feature;
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &q;
    dci.enabledExtensionCount = 1;
    dci.ppEnabledExtensionNames = &ext;
    if (VkResult r = vkCreateDevice(chosen, &dci, nullptr, &d.device); r != VK_SUCCESS) {
        d.device = VK_NULL_HANDLE;
        return skip("vkCreateDevice failed (" + std::string(vk::resultString(r)) + ")");
    }
    // The compositor's layouts (Compositor::passSetBindings, 16 bytes of push constants: gpu::LevelPush;
    // the compose pass's own, ComposePass::setBindings).
    auto makeLayout = [&](const std::vector<VkDescriptorSetLayoutBinding>& bindings, uint32_t pushBytes,
                          VkDescriptorSetLayout& set, VkPipelineLayout& layout) {
        VkDescriptorSetLayoutCreateInfo sl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        sl.bindingCount = uint32_t(bindings.size());
        sl.pBindings = bindings.data();
        if (vkCreateDescriptorSetLayout(d.device, &sl, nullptr, &set) != VK_SUCCESS) return false;
        const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushBytes};
        VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        pl.setLayoutCount = 1;
        pl.pSetLayouts = &set;
        pl.pushConstantRangeCount = 1;
        pl.pPushConstantRanges = &push;
        return vkCreatePipelineLayout(d.device, &pl, nullptr, &layout) == VK_SUCCESS;
    };
    if (!makeLayout(Compositor::passSetBindings(), sizeof(gpu::LevelPush), d.setLayout, d.layout))
        return fail("the passes' pipeline layout");
    if (!makeLayout(ComposePass::setBindings(), ComposePass::kPushBytes, d.composeSetLayout, d.composeLayout))
        return fail("compose pipeline layout");
    auto getProps = reinterpret_cast<PFN_vkGetPipelineExecutablePropertiesKHR>(
        vkGetDeviceProcAddr(d.device, "vkGetPipelineExecutablePropertiesKHR"));
    auto getStats = reinterpret_cast<PFN_vkGetPipelineExecutableStatisticsKHR>(
        vkGetDeviceProcAddr(d.device, "vkGetPipelineExecutableStatisticsKHR"));
    if (!getProps || !getStats) return skip("the device exposes no vkGetPipelineExecutable*KHR entry points");

    for (const VariantKey& k : keys) {
        const std::span<const uint32_t> code = spirv(k.shader);
        VkShaderModuleCreateInfo smci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        smci.codeSize = code.size_bytes();
        smci.pCode = code.data();
        VkShaderModule module;
        if (vkCreateShaderModule(d.device, &smci, nullptr, &module) != VK_SUCCESS)
            return fail("shader module " + toString(k));
        constexpr uint32_t n = uint32_t(std::tuple_size_v<decltype(k.constants)>);
        VkSpecializationMapEntry entries[n];
        for (uint32_t i = 0; i < n; ++i) entries[i] = {i, uint32_t(i * sizeof(uint32_t)), sizeof(uint32_t)};
        const VkSpecializationInfo spec{n, entries, sizeof(k.constants), k.constants.data()};
        VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        ci.flags = VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
        ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        ci.stage.module = module;
        ci.stage.pName = "main";
        ci.stage.pSpecializationInfo = &spec;
        ci.layout = k.shader == ShaderId::Compose ? d.composeLayout : d.layout;
        VkPipeline pipeline;
        const VkResult r = vkCreateComputePipelines(d.device, VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline);
        vkDestroyShaderModule(d.device, module, nullptr);
        if (r != VK_SUCCESS) return fail("compiling " + toString(k) + ": " + vk::resultString(r));
        VkPipelineInfoKHR pi{VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR};
        pi.pipeline = pipeline;
        uint32_t ne = 0;
        getProps(d.device, &pi, &ne, nullptr);
        std::vector<VkPipelineExecutablePropertiesKHR> exes(ne, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_PROPERTIES_KHR});
        getProps(d.device, &pi, &ne, exes.data());
        for (uint32_t e = 0; e < ne; ++e) {
            if (!(exes[e].stages & VK_SHADER_STAGE_COMPUTE_BIT)) continue;
            VkPipelineExecutableInfoKHR ei{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR};
            ei.pipeline = pipeline;
            ei.executableIndex = e;
            uint32_t ns = 0;
            getStats(d.device, &ei, &ns, nullptr);
            std::vector<VkPipelineExecutableStatisticKHR> stats(ns,
                                                                {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR});
            getStats(d.device, &ei, &ns, stats.data());
            std::printf("executable\t%s\t%u\n", toString(k).c_str(), exes[e].subgroupSize);
            for (const VkPipelineExecutableStatisticKHR& s : stats) {
                double val = 0;
                switch (s.format) {
                    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR:
                        val = s.value.b32;
                        break;
                    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR:
                        val = double(s.value.i64);
                        break;
                    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR:
                        val = double(s.value.u64);
                        break;
                    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR:
                        val = s.value.f64;
                        break;
                    default:
                        continue;
                }
                std::printf("stat\t%s\t%d\t%.17g\n", s.name, int(s.format), val);
            }
            break;
        }
        vkDestroyPipeline(d.device, pipeline, nullptr);
    }
    std::fflush(stdout);
    if (validationMessages > 0) return fail(std::to_string(validationMessages) + " validation messages");
    return 0;
}

std::vector<CostRow> costRows(const CostCell& cell, const std::map<VariantKey, ExecutableStats>& stats) {
    const GpuFigures& g = *cell.gpu;
    const double px = double(cell.width) * cell.height * cell.eyes;
    const double tiles = double(groupsOf(cell.width, gpu::WRS_TILE) * groupsOf(cell.height, gpu::WRS_TILE) * cell.eyes);
    const std::string size =
        std::to_string(cell.eyes) + "x" + std::to_string(cell.width) + "x" + std::to_string(cell.height);
    std::vector<CostRow> rows;
    CostRow total{g.name, size, std::string(toString(cell.method)), "total", "all", true};
    for (const PipelineVariant& v : cell.variants) {
        CostRow r{g.name, size, std::string(toString(cell.method)), v.pass, tileClassName(v.tileClass)};
        auto it = stats.find(VariantKey{v.shader, v.constants});
        if (it != stats.end()) r.stats = it->second;
        const bool whole = v.tileClass < 0;  // the whole image or a known part of it (cover)
        r.groups = whole ? double(v.groups) : cell.shares[std::size_t(v.tileClass)] * tiles;
        // A tile-class group covers its tile's pixels; a whole-image pass covers the image.
        const double covered = whole ? px * v.cover : std::min(px, r.groups * gpu::WRS_TILE * gpu::WRS_TILE);
        r.share = covered / px;
        // ACO's inverse throughput is in cycles per wave64 on one SIMD, whatever the wave size.
        const double waves64 = r.groups * v.invocationsPerGroup / 64.0;
        const double cycles = waves64 * r.stats.invThroughput;
        r.cyclesPerPx = covered > 0 ? cycles / covered : 0.0;
        r.bytesPerPx = v.bytesPerPx;
        r.aluUs = cycles / g.simds / g.clockMHz;
        r.memUs = covered * v.bytesPerPx / (g.bandwidthGBs * 1e3);
        rows.push_back(r);
    }
    // A phase (a run of dispatches with no barrier between them) lasts at least the latency of its
    // slowest wave: the shortfall of the phase's throughput cycles goes to that wave's row. A dispatch
    // with no groups (an empty tile list) has no wave.
    for (std::size_t first = 0, end; first < rows.size(); first = end) {
        const int phase = cell.variants[first].phase;
        end = first + 1;
        while (phase != kOwnPhase && end < rows.size() && cell.variants[end].phase == phase) ++end;
        double throughput = 0, latency = 0;
        std::size_t slowest = first;
        for (std::size_t j = first; j < end; ++j) {
            throughput += rows[j].aluUs * g.clockMHz;
            if (rows[j].groups > 0 && rows[j].stats.latency > latency) latency = rows[j].stats.latency, slowest = j;
        }
        if (latency > throughput) rows[slowest].aluUs += (latency - throughput) / g.clockMHz;
    }
    for (CostRow& r : rows) {
        r.predictedUs = std::max(r.aluUs, r.memUs);
        const double covered = r.share * px;
        total.groups += r.groups;
        total.cyclesPerPx += r.cyclesPerPx * covered / px;
        total.bytesPerPx += covered * r.bytesPerPx / px;
        total.aluUs += r.aluUs;
        total.memUs += r.memUs;
        total.predictedUs += r.predictedUs;
    }
    total.share = 1.0;
    rows.push_back(total);
    return rows;
}

std::string_view costCsvHeader() {
    return "gpu,size,method,pass,class,instructions,vgprs,waves_per_simd,subgroup_size,inv_throughput,cycles_per_px,"
           "bytes_per_px,share,alu_us,mem_us,predicted_us,sgprs,latency,groups,bound";
}

namespace {

std::string num(double v, int prec = 2) {
    if (!std::isfinite(v)) return "n/a";
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(prec);
    s << v;
    return s.str();
}

const char* bound(double alu, double mem) { return alu >= mem ? "arithmetic" : "memory"; }

}  // namespace

std::string costTotalsMarkdown(const std::vector<CostRow>& rows) {
    std::ostringstream md;
    md << "| GPU | size | method | alu µs | mem µs | predicted µs | ×fov | bound "
          "|\n|---|---|---|---|---|---|---|---|\n";
    for (const CostRow& r : rows) {
        if (!r.total) continue;
        double fov = std::numeric_limits<double>::quiet_NaN();
        for (const CostRow& f : rows)
            if (f.total && f.gpu == r.gpu && f.size == r.size && f.method == "fov") fov = f.predictedUs;
        md << "| " << r.gpu << " | " << r.size << " | " << r.method << " | " << num(r.aluUs, 1) << " | "
           << num(r.memUs, 1) << " | " << num(r.predictedUs, 1) << " | " << num(r.predictedUs / fov) << " | "
           << bound(r.aluUs, r.memUs) << " |\n";
    }
    return md.str();
}

Status writeCostModel(const std::vector<CostRow>& rows, const std::vector<std::string>& skipped,
                      const std::string& cellDescription, const std::string& dir) {
    std::ofstream csv(dir + "/cost_model.csv"), md(dir + "/cost_model.md");
    if (!csv || !md) return Error{1, "cannot write " + dir + "/cost_model.{csv,md}"};
    csv.precision(7);
    csv << costCsvHeader() << '\n';
    for (const CostRow& r : rows) {
        csv << r.gpu << ',' << r.size << ',' << r.method << ',' << r.pass << ',' << r.cls << ',';
        if (r.total)
            csv << ",,,,,";
        else
            csv << r.stats.instructions << ',' << r.stats.vgprs << ',' << r.stats.wavesPerSimd << ','
                << r.stats.subgroupSize << ',' << r.stats.invThroughput << ',';
        csv << r.cyclesPerPx << ',' << r.bytesPerPx << ',' << r.share << ',' << r.aluUs << ',' << r.memUs << ','
            << r.predictedUs << ',';
        if (r.total)
            csv << ",,";
        else
            csv << r.stats.sgprs << ',' << r.stats.latency << ',';
        csv << r.groups << ',' << bound(r.aluUs, r.memUs) << '\n';
    }

    md << "# wrsfov cost model (static estimate)\n\n"
       << cellDescription
       << "\n\nEvery pipeline the cell dispatches (pass × specialisation constants × tile class, "
          "eval/cost_model.cpp `pipelineVariants`) compiled on RADV's null device for each GPU's family; the "
          "statistics are those of Mesa's ACO compiler (VK_KHR_pipeline_executable_properties). Per row: "
          "`alu µs = waves64 × inverse throughput / SIMDs / clock`, where the dispatches recorded with no barrier "
          "between them (a phase: the classification and the `mip` pyramid, the tile classes of a pass that does "
          "not write what it reads) last at least their slowest wave's latency, added to that wave's row where "
          "the phase's throughput falls short of it; `mem µs = bytes / bandwidth`, `predicted = max(alu, mem)`; a "
          "total sums its rows. No cache "
          "model, no dispatch overhead, peak bandwidth: estimates to compare passes and methods, not timings "
          "(docs/speed.md \"Cost model\").\n\n";
    if (!skipped.empty()) {
        md << "**Skipped** (no statistics):\n\n";
        for (const std::string& s : skipped) md << "- " << s << "\n";
        md << "\n";
    }
    md << "## GPUs\n\n| GPU | product | CUs | SIMD32 | clock MHz | GB/s | HMD cell per eye | source |\n"
          "|---|---|---|---|---|---|---|---|\n";
    for (const GpuFigures& g : gpuTable())
        md << "| " << g.name << " | " << g.product << " | " << g.computeUnits << " | " << g.simds << " | "
           << num(g.clockMHz, 0) << " | " << num(g.bandwidthGBs, 0) << " | " << g.eyeWidth << "×" << g.eyeHeight
           << " | " << g.source << " |\n";
    if (rows.empty()) {
        md << "\nNo rows: no target gave statistics.\n";
        return {};
    }
    md << "\n## Totals per frame (both eyes)\n\n" << costTotalsMarkdown(rows);
    // Per GPU and size: the rows, then one verdict per method and pass.
    std::vector<std::pair<std::string, std::string>> groups;
    for (const CostRow& r : rows)
        if (std::find(groups.begin(), groups.end(), std::pair{r.gpu, r.size}) == groups.end())
            groups.emplace_back(r.gpu, r.size);
    for (const auto& [gpuName, size] : groups) {
        md << "\n## " << gpuName << ", " << size
           << "\n\n| method | pass | class | instr. | VGPRs | waves/SIMD | wave | "
              "inv. thr. | cycles/px | B/px | share | alu µs | mem µs | predicted µs |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        for (const CostRow& r : rows) {
            if (r.gpu != gpuName || r.size != size || r.total) continue;
            md << "| " << r.method << " | " << r.pass << " | " << r.cls << " | " << num(r.stats.instructions, 0)
               << " | " << num(r.stats.vgprs, 0) << " | " << num(r.stats.wavesPerSimd, 0) << " | "
               << r.stats.subgroupSize << " | " << num(r.stats.invThroughput, 0) << " | " << num(r.cyclesPerPx, 2)
               << " | " << num(r.bytesPerPx, 2) << " | " << num(r.share, 3) << " | " << num(r.aluUs, 2) << " | "
               << num(r.memUs, 2) << " | " << num(r.predictedUs, 2) << " |\n";
        }
        md << "\nVerdicts:\n\n";
        std::vector<std::pair<std::string, std::string>> passes;  // (method, pass) in order
        for (const CostRow& r : rows)
            if (r.gpu == gpuName && r.size == size && !r.total &&
                std::find(passes.begin(), passes.end(), std::pair{r.method, r.pass}) == passes.end())
                passes.emplace_back(r.method, r.pass);
        for (const auto& [method, pass] : passes) {
            double alu = 0, mem = 0, pred = 0;
            for (const CostRow& r : rows)
                if (r.gpu == gpuName && r.size == size && r.method == method && r.pass == pass && !r.total)
                    alu += r.aluUs, mem += r.memUs, pred += r.predictedUs;
            md << "- " << method << " / " << pass << ": " << bound(alu, mem) << "-bound (alu " << num(alu, 1)
               << " µs, memory " << num(mem, 1) << " µs, predicted " << num(pred, 1) << " µs)\n";
        }
    }
    return {};
}

}  // namespace wrsfov::eval
