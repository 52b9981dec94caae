// CUDA-GL interop for the renderer's particle buffer: the only code that sees both GL and CUDA.
// The buffer is registered once (write-discard) and mapped once per frame; a kernel writes the
// instances straight from simulation memory, so no particle data crosses PCIe to be drawn.
#pragma once

#include <string>

namespace corebox {

class CudaParticleSource;

class CudaGlInterop {
public:
    // Needs the GL context current. Checks with cudaGLGetDevices that it runs on `cudaDevice`;
    // throws DeviceError naming both devices when it does not (the caller then uses the copy path).
    CudaGlInterop(unsigned int glBuffer, int cudaDevice);
    ~CudaGlInterop();
    CudaGlInterop(const CudaGlInterop&) = delete;
    CudaGlInterop& operator=(const CudaGlInterop&) = delete;

    unsigned int buffer() const { return m_buffer; }
    // Map, let `source` write n instances, unmap.
    void fill(CudaParticleSource& source, bool keyIsSpeed);

private:
    unsigned int m_buffer;
    void* m_resource = nullptr;  // cudaGraphicsResource_t
};

}  // namespace corebox
