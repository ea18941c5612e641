// The loader <-> runtime and loader <-> API layer negotiation of the OpenXR loader specification
// ("Runtime Interface Negotiation", "API Layer Interface Negotiation"). Debian's OpenXR 1.0.20 headers do not ship openxr_loader_negotiation.h, so the
// structures are declared here from the specification; names, values and layout follow it.
#pragma once

#include <openxr/openxr.h>

#include <cstddef>
#include <cstdint>

extern "C" {

typedef enum XrLoaderInterfaceStructs {
    XR_LOADER_INTERFACE_STRUCT_UNINTIALIZED = 0,
    XR_LOADER_INTERFACE_STRUCT_LOADER_INFO = 1,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST = 2,
    XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST = 3,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO = 4,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO = 5,
    XR_LOADER_INTERFACE_STRUCTS_MAX_ENUM = 0x7FFFFFFF
} XrLoaderInterfaceStructs;

#define XR_LOADER_INFO_STRUCT_VERSION 1
#define XR_RUNTIME_INFO_STRUCT_VERSION 1
#define XR_CURRENT_LOADER_RUNTIME_VERSION 1

/// What the loader offers: the interface and API versions it can speak.
typedef struct XrNegotiateLoaderInfo {
    XrLoaderInterfaceStructs structType;  // XR_LOADER_INTERFACE_STRUCT_LOADER_INFO
    uint32_t structVersion;               // XR_LOADER_INFO_STRUCT_VERSION
    size_t structSize;                    // sizeof(XrNegotiateLoaderInfo)
    uint32_t minInterfaceVersion;
    uint32_t maxInterfaceVersion;
    XrVersion minApiVersion;
    XrVersion maxApiVersion;
} XrNegotiateLoaderInfo;

/// What the runtime answers: the versions it chose and its xrGetInstanceProcAddr.
typedef struct XrNegotiateRuntimeRequest {
    XrLoaderInterfaceStructs structType;  // XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST
    uint32_t structVersion;               // XR_RUNTIME_INFO_STRUCT_VERSION
    size_t structSize;                    // sizeof(XrNegotiateRuntimeRequest)
    uint32_t runtimeInterfaceVersion;     // out
    XrVersion runtimeApiVersion;          // out
    PFN_xrGetInstanceProcAddr getInstanceProcAddr;  // out
} XrNegotiateRuntimeRequest;

typedef XrResult(XRAPI_PTR* PFN_xrNegotiateLoaderRuntimeInterface)(const XrNegotiateLoaderInfo* loaderInfo,
                                                                   XrNegotiateRuntimeRequest* runtimeRequest);

// ---- API layers ----
#define XR_CURRENT_LOADER_API_LAYER_VERSION 1
#define XR_API_LAYER_INFO_STRUCT_VERSION 1
#define XR_API_LAYER_NEXT_INFO_STRUCT_VERSION 1
#define XR_API_LAYER_CREATE_INFO_STRUCT_VERSION 1
#define XR_API_LAYER_MAX_SETTINGS_PATH_SIZE 512

struct XrApiLayerCreateInfo;
typedef XrResult(XRAPI_PTR* PFN_xrCreateApiLayerInstance)(const XrInstanceCreateInfo* info,
                                                           const struct XrApiLayerCreateInfo* layerInfo,
                                                           XrInstance* instance);

/// One link of the chain below a layer: the next layer's (or the runtime's) entry points.
typedef struct XrApiLayerNextInfo {
    XrLoaderInterfaceStructs structType;  // XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO
    uint32_t structVersion;               // XR_API_LAYER_NEXT_INFO_STRUCT_VERSION
    size_t structSize;                    // sizeof(XrApiLayerNextInfo)
    char layerName[XR_MAX_API_LAYER_NAME_SIZE];
    PFN_xrGetInstanceProcAddr nextGetInstanceProcAddr;
    PFN_xrCreateApiLayerInstance nextCreateApiLayerInstance;
    struct XrApiLayerNextInfo* next;
} XrApiLayerNextInfo;

/// What the loader passes to xrCreateApiLayerInstance.
typedef struct XrApiLayerCreateInfo {
    XrLoaderInterfaceStructs structType;  // XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO
    uint32_t structVersion;               // XR_API_LAYER_CREATE_INFO_STRUCT_VERSION
    size_t structSize;                    // sizeof(XrApiLayerCreateInfo)
    void* loaderInstance;
    char settings_file_location[XR_API_LAYER_MAX_SETTINGS_PATH_SIZE];
    XrApiLayerNextInfo* nextInfo;
} XrApiLayerCreateInfo;

/// What a layer answers to the loader's negotiation.
typedef struct XrNegotiateApiLayerRequest {
    XrLoaderInterfaceStructs structType;  // XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST
    uint32_t structVersion;               // XR_API_LAYER_INFO_STRUCT_VERSION
    size_t structSize;                    // sizeof(XrNegotiateApiLayerRequest)
    uint32_t layerInterfaceVersion;       // out
    XrVersion layerApiVersion;            // out
    PFN_xrGetInstanceProcAddr getInstanceProcAddr;         // out
    PFN_xrCreateApiLayerInstance createApiLayerInstance;  // out
} XrNegotiateApiLayerRequest;

}  // extern "C"
