// Stream capture into an instantiated CUDA graph, for work a backend enqueues again and again with the
// same arguments (the RK step at small N, a collision round's cell-list build): launching the graph
// costs the host one call instead of one per kernel.
#pragma once

#include <cuda_runtime_api.h>

#include <stdexcept>
#include <string>

namespace corebox {

// What enqueue() puts on `stream`, captured (relaxed mode: other threads may go on calling CUDA) and
// instantiated; null where the driver refused, or where enqueue threw a runtime_error (DeviceError
// included): then nothing of it was launched, and the error is cleared. Any other exception ends the
// capture and goes on.
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
        } catch (...) {
            cudaStreamEndCapture(stream, &captured);
            if (captured) cudaGraphDestroy(captured);
            cudaGetLastError();
            throw;
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

// Within a capture of `stream` (captureGraph): gate(handle) enqueues on `stream` what sets the IF
// condition `handle` (from a kernel: cudaGraphSetConditional; 0 at every launch until it does), then an
// IF node follows it whose body is what body(helper) enqueues on `helper`, an idle stream of the same
// device that captures it (a stream captures one graph at a time; a body may hold an IF of its own, with
// a helper of its own). Throws a runtime_error where the driver refuses (conditional nodes came with
// CUDA 12.4; these calls are CUDA 13's), which makes captureGraph give up the graph.
template <class Gate, class Body>
void enqueueIf(cudaStream_t stream, cudaStream_t helper, Gate&& gate, Body&& body) {
    auto check = [](cudaError_t e, const char* what) {
        if (e != cudaSuccess)
            throw std::runtime_error(std::string("conditional graph node: ") + what + ": " + cudaGetErrorString(e));
    };
    cudaStreamCaptureStatus status{};
    cudaGraph_t graph = nullptr;
    const cudaGraphNode_t* after = nullptr;
    size_t afterCount = 0;
    check(cudaStreamGetCaptureInfo(stream, &status, nullptr, &graph, &after, nullptr, &afterCount), "capture info");
    if (status != cudaStreamCaptureStatusActive)
        throw std::runtime_error("conditional graph node: the stream is not capturing");
    cudaGraphConditionalHandle handle{};
    check(cudaGraphConditionalHandleCreate(&handle, graph, 0, cudaGraphCondAssignDefault), "handle");
    gate(handle);
    check(cudaStreamGetCaptureInfo(stream, &status, nullptr, &graph, &after, nullptr, &afterCount), "capture info");
    cudaGraphNodeParams params{};
    params.type = cudaGraphNodeTypeConditional;
    params.conditional.handle = handle;
    params.conditional.type = cudaGraphCondTypeIf;
    params.conditional.size = 1;
    cudaGraphNode_t node = nullptr;
    check(cudaGraphAddNode(&node, graph, after, nullptr, afterCount, &params), "add");
    check(cudaStreamUpdateCaptureDependencies(stream, &node, nullptr, 1, cudaStreamSetCaptureDependencies),
          "dependencies");
    check(cudaStreamBeginCaptureToGraph(helper, params.conditional.phGraph_out[0], nullptr, nullptr, 0,
                                        cudaStreamCaptureModeRelaxed),
          "body capture");
    bool captured = false;
    try {
        body(helper);
        captured = true;
    } catch (const std::runtime_error&) {
    } catch (...) {  // the helper leaves its capture whatever went wrong
        cudaGraph_t ended = nullptr;
        cudaStreamEndCapture(helper, &ended);
        throw;
    }
    cudaGraph_t ended = nullptr;
    const cudaError_t end = cudaStreamEndCapture(helper, &ended);
    if (!captured) throw std::runtime_error("conditional graph node: the body failed");
    check(end, "body capture end");
}

}  // namespace corebox
