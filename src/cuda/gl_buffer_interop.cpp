#include "gl_buffer_interop.h"

#include <epoxy/gl.h>  // before cuda_gl_interop.h, which wants GL types
// clang-format off
#include <cuda_gl_interop.h>
// clang-format on

#include <exception>

#include "cuda_check.h"

namespace corebox {

CudaGlInterop::CudaGlInterop(unsigned int glBuffer, int cudaDevice) : m_buffer(glBuffer) {
    unsigned int count = 0;
    int devices[8] = {};
    const cudaError_t status = cudaGLGetDevices(&count, devices, 8, cudaGLDeviceListAll);
    if (status != cudaSuccess || count == 0) {
        cudaGetLastError();
        throw DeviceError("the GL context does not run on a CUDA device (cudaGLGetDevices: " + std::string(cudaGetErrorString(status)) +
                          "); CUDA device " + std::to_string(cudaDevice) + " cannot share its buffers");
    }
    bool match = false;
    std::string found;
    for (unsigned int k = 0; k < count; ++k) {
        match = match || devices[k] == cudaDevice;
        found += (k ? ", " : "") + std::to_string(devices[k]);
    }
    if (!match) {
        throw DeviceError("the GL context runs on CUDA device " + found + " but the simulation runs on CUDA device " +
                          std::to_string(cudaDevice));
    }
    cudaGraphicsResource_t resource = nullptr;
    cudaCheck(cudaGraphicsGLRegisterBuffer(&resource, glBuffer, cudaGraphicsRegisterFlagsWriteDiscard), "cudaGraphicsGLRegisterBuffer");
    m_resource = resource;
}

CudaGlInterop::~CudaGlInterop() {
    if (m_resource) cudaGraphicsUnregisterResource(static_cast<cudaGraphicsResource_t>(m_resource));
}

CudaGlInterop::Mapping::Mapping(CudaGlInterop& interop) : m_interop(interop) {
    auto resource = static_cast<cudaGraphicsResource_t>(interop.m_resource);
    cudaCheck(cudaGraphicsMapResources(1, &resource, nullptr), "cudaGraphicsMapResources");
    void* pointer = nullptr;
    size_t bytes = 0;
    const cudaError_t mapped = cudaGraphicsResourceGetMappedPointer(&pointer, &bytes, resource);
    if (mapped != cudaSuccess) {
        cudaGraphicsUnmapResources(1, &resource, nullptr);
        cudaCheck(mapped, "cudaGraphicsResourceGetMappedPointer");
    }
    m_instances = static_cast<ParticleInstance*>(pointer);
}

// Unmapping fails only with a broken context; report it unless an exception is already on its way.
CudaGlInterop::Mapping::~Mapping() noexcept(false) {
    auto resource = static_cast<cudaGraphicsResource_t>(m_interop.m_resource);
    const cudaError_t status = cudaGraphicsUnmapResources(1, &resource, nullptr);
    if (std::uncaught_exceptions() == 0) cudaCheck(status, "cudaGraphicsUnmapResources");
}

}  // namespace corebox
