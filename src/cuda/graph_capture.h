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

// A graph of a gate and an IF body: gate(handle) enqueues what sets the condition `handle` (from a
// kernel: cudaGraphSetConditional; 0 at every launch until it does), body() what runs only where it set
// it non-zero; both captured as captureGraph does. Null where the driver refused (conditional nodes need
// CUDA 12.4) or either threw a runtime_error: then nothing of them was launched.
template <class Gate, class Body>
cudaGraphExec_t captureConditionalGraph(cudaStream_t stream, Gate&& gate, Body&& body) {
    cudaGraph_t graph = nullptr;
    cudaGraphExec_t exec = nullptr;
    cudaGraphConditionalHandle handle{};
    bool made = cudaGraphCreate(&graph, 0) == cudaSuccess &&
                cudaGraphConditionalHandleCreate(&handle, graph, 0, cudaGraphCondAssignDefault) == cudaSuccess;
    // Captures what enqueue() puts on the stream into `into`, after what it holds.
    auto captureInto = [&](cudaGraph_t into, auto&& enqueue, auto&& beforeEnd) {
        if (!made) return;
        made = cudaStreamBeginCaptureToGraph(stream, into, nullptr, nullptr, 0, cudaStreamCaptureModeRelaxed) ==
               cudaSuccess;
        if (!made) return;
        try {
            enqueue();
            beforeEnd();
        } catch (const std::runtime_error&) {
            made = false;
        }
        cudaGraph_t ended = nullptr;
        made = cudaStreamEndCapture(stream, &ended) == cudaSuccess && made;
    };
    cudaGraph_t bodyGraph = nullptr;
    captureInto(graph, [&] { gate(handle); }, [&] {
        // The IF node after the gate, made the capture's last node.
        cudaStreamCaptureStatus status{};
        cudaGraph_t capturing = nullptr;
        const cudaGraphNode_t* after = nullptr;
        size_t afterCount = 0;
        if (cudaStreamGetCaptureInfo(stream, &status, nullptr, &capturing, &after, nullptr, &afterCount) != cudaSuccess)
            throw std::runtime_error("capture info");
        cudaGraphNodeParams params{};
        params.type = cudaGraphNodeTypeConditional;
        params.conditional.handle = handle;
        params.conditional.type = cudaGraphCondTypeIf;
        params.conditional.size = 1;
        cudaGraphNode_t node = nullptr;
        if (cudaGraphAddNode(&node, capturing, after, nullptr, afterCount, &params) != cudaSuccess)
            throw std::runtime_error("conditional node");
        bodyGraph = params.conditional.phGraph_out[0];
        if (cudaStreamUpdateCaptureDependencies(stream, &node, nullptr, 1, cudaStreamSetCaptureDependencies) !=
            cudaSuccess)
            throw std::runtime_error("capture dependencies");
    });
    captureInto(bodyGraph, [&] { body(); }, [] {});
    made = made && cudaGraphInstantiate(&exec, graph, 0) == cudaSuccess;
    if (graph) cudaGraphDestroy(graph);
    if (made) return exec;
    if (exec) cudaGraphExecDestroy(exec);
    cudaGetLastError();
    return nullptr;
}

}  // namespace corebox
