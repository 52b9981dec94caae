// CUDA-GL interop for the renderer's particle buffer: the only code that sees both GL and CUDA (its
// own library, so the CUDA backend does not link GL). The buffer is registered once (write-discard)
// and mapped once per frame; while mapped, a backend writes instances into it with
// writeInstances(InstanceTarget::Memory::Device), so no particle data crosses PCIe to be drawn.
#pragma once

#include "particle_instance.h"

namespace corebox {

class CudaGlInterop {
public:
    // Needs the GL context current. Checks with cudaGLGetDevices that it runs on `cudaDevice`;
    // throws DeviceError naming both devices when it does not (the caller then uses the copy path).
    CudaGlInterop(unsigned int glBuffer, int cudaDevice);
    ~CudaGlInterop();
    CudaGlInterop(const CudaGlInterop&) = delete;
    CudaGlInterop& operator=(const CudaGlInterop&) = delete;

    unsigned int buffer() const { return m_buffer; }

    // The buffer mapped for the lifetime of the object: instances() is a device pointer on the
    // interop device, valid until destruction, which unmaps.
    class Mapping {
    public:
        explicit Mapping(CudaGlInterop& interop);
        ~Mapping() noexcept(false);
        Mapping(const Mapping&) = delete;
        Mapping& operator=(const Mapping&) = delete;
        ParticleInstance* instances() const { return m_instances; }

    private:
        CudaGlInterop& m_interop;
        ParticleInstance* m_instances = nullptr;
    };

private:
    unsigned int m_buffer;
    void* m_resource = nullptr;  // cudaGraphicsResource_t
};

}  // namespace corebox
