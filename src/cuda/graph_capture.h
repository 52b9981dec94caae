// Stream capture into an instantiated CUDA graph, for work a backend enqueues again and again with the
// same arguments (the RK step at small N, a collision round's cell-list build): launching the graph
// costs the host one call instead of one per kernel.
#pragma once

#include <cuda_runtime_api.h>

#include <stdexcept>

namespace corebox {

// What enqueue() puts on `stream`, captured (relaxed mode: other threads may go on calling CUDA) and
// instantiated; null where the driver refused, or where enqueue threw a runtime_error (DeviceError
// included): then nothing of it was launched, and the error is cleared.
template <class Enqueue>
cudaGraphExec_t captureGraph(cudaStream_t stream, Enqueue&& enqueue) {
    cudaGraph_t captured = nullptr;
    cudaGraphExec_t exec = nullptr;
    bool made = cudaStreamBeginCapture(stream, cudaStreamCaptureModeRelaxed) == cudaSuccess;
    if (made) {
        try {
            enqueue();
        } catch (const std::runtime_error&) {
            made = false;
        }
        made = cudaStreamEndCapture(stream, &captured) == cudaSuccess && made;
    }
    made = made && cudaGraphInstantiate(&exec, captured, 0) == cudaSuccess;
    if (captured) cudaGraphDestroy(captured);
    if (made) return exec;
    if (exec) cudaGraphExecDestroy(exec);
    cudaGetLastError();
    return nullptr;
}

}  // namespace corebox
