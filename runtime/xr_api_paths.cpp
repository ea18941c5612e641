// Paths: the instance's interned path strings, xrStringToPath and xrPathToString.
#include "runtime/xr_objects.h"
#include "runtime/xr_verify.h"

namespace wrsfov::xr {

XrPath Instance::path(const std::string& s) {
    auto it = pathIds.find(s);
    if (it != pathIds.end()) return it->second;
    paths.push_back(s);
    const XrPath id = XrPath(paths.size());
    pathIds.emplace(s, id);
    return id;
}

std::string Instance::pathString(XrPath p) const {
    if (p == XR_NULL_PATH || p > paths.size()) return {};
    return paths[p - 1];
}

XRAPI_ATTR XrResult XRAPI_CALL xrStringToPath(XrInstance h, const char* pathString, XrPath* path) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!pathString || !path) return XR_ERROR_VALIDATION_FAILURE;
    if (!wellFormedPath(pathString)) return XR_ERROR_PATH_FORMAT_INVALID;
    *path = inst->path(pathString);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrPathToString(XrInstance h, XrPath path, uint32_t capacity, uint32_t* countOutput,
                                              char* buffer) {
    std::lock_guard lock(stateMutex(h));
    Instance* inst = getInstance(h);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    const std::string s = inst->pathString(path);
    if (s.empty()) return XR_ERROR_PATH_INVALID;
    return fillString(capacity, countOutput, buffer, s);
}

}  // namespace wrsfov::xr
