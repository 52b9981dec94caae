// The CUDA backend's explicit RK step as one CUDA graph (design note in cuda_device.h).
#include "cuda_device.h"

namespace corebox {

// One GPU, all pairs: nothing in the stages waits for the device (lists check displacements on the host,
// several GPUs order their exchanges from the host).
template <class Real>
bool CudaDevice<Real>::rkGraphApplies() const {
    return m_fusedSteps && gpuCount() == 1 && !useLists() && m_n > 0;
}

template <class Real>
void CudaDevice<Real>::rkStep(int stages, double dt) {
    if (!rkGraphApplies()) {
        Backend::rkStep(stages, dt);
        return;
    }
    Replica<Real>& r = home();
    const size_t rows = size_t(m_tableau.stages) * size_t(m_n);
    r.kx.resize(rows);
    r.kv.resize(rows);
    // The deferred snapshot (keepSnapshot) is taken by the first stage's forces: in the graph.
    const RkGraphKey key{m_modelGeneration, dt, stages, r.x.data(), r.xStage.data(), r.kx.data(), r.kv.data(), m_snapshotPending};
    RkGraph* graph = nullptr;
    for (RkGraph& g : m_rkGraphs)
        if (g.key == key) graph = &g;
    if (!graph) {  // a step not seen before (an adaptive step's dt, a new model): the plain launches, noted
        RkGraph& slot = m_rkGraphs[size_t(m_rkGraphNext)];
        m_rkGraphNext = (m_rkGraphNext + 1) % int(m_rkGraphs.size());
        slot.reset();
        slot.key = key;
        Backend::rkStep(stages, dt);
        return;
    }
    cudaStream_t s = stream();
    if (!graph->exec) {  // seen once before: captured now, launched from here on
        const int window = m_timingWindow;
        m_timingWindow = -1;  // no per-pass timing events inside the graph: the pair below brackets it
        const int64_t evaluations = m_allPairsEvaluations, passes = m_fullPasses;
        cudaCheck(cudaStreamBeginCapture(s, cudaStreamCaptureModeRelaxed), "graph capture");
        try {
            Backend::rkStep(stages, dt);
        } catch (...) {
            cudaGraph_t broken = nullptr;
            cudaStreamEndCapture(s, &broken);
            if (broken) cudaGraphDestroy(broken);
            m_timingWindow = window;
            throw;
        }
        cudaGraph_t captured = nullptr;
        m_timingWindow = window;
        cudaCheck(cudaStreamEndCapture(s, &captured), "graph capture");
        const cudaError_t made = cudaGraphInstantiate(&graph->exec, captured, 0);
        cudaGraphDestroy(captured);
        cudaCheck(made, "graph instantiate");
        graph->evaluations = m_allPairsEvaluations - evaluations;
        graph->passes = m_fullPasses - passes;
        m_allPairsEvaluations = evaluations;  // counted below, as for every launch of the graph
        m_fullPasses = passes;
    } else {
        m_snapshotPending = false;  // the graph takes it
        beforeStateChange();        // as the first stage's forces would
    }
    markForceTime();
    cudaCheck(cudaGraphLaunch(graph->exec, s), "graph launch");
    markForceTime();
    m_allPairsEvaluations += graph->evaluations;
    m_fullPasses += graph->passes;
    // What the stages' calls leave on the host side (rkStage, stageForces, forcePass, rkSolution).
    m_homeCurrent = true;
    m_forecast.stage = 0;
    m_accelerationMatchesX = false;
    m_screenPending = false;
    m_listAtX = false;
}

template <class Real>
void CudaDevice<Real>::RkGraph::reset() {
    if (exec) cudaGraphExecDestroy(exec);
    exec = nullptr;
    key = RkGraphKey{};
    evaluations = passes = 0;
}

template class CudaDevice<float>;
template class CudaDevice<double>;

}  // namespace corebox
