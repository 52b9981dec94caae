// The CUDA backend's explicit RK step as one CUDA graph (design note in cuda_device.h).
#include "cuda_device.h"
#include "graph_capture.h"

namespace corebox {

// One GPU, all pairs: nothing in the stages waits for the device (lists check displacements on the host,
// several GPUs order their exchanges from the host).
template <class Real>
bool CudaDevice<Real>::rkGraphApplies() const {
    return m_fusedSteps && !m_rkGraphsOff && gpuCount() == 1 && !useLists() && m_n > 0;
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
    if (!graph->exec && !captureRkStep(*graph, stages, dt)) {
        Backend::rkStep(stages, dt);  // the capture launched nothing: the step as plain launches
        return;
    }
    if (graph->launched) {
        m_snapshotPending = false;  // the graph takes it
        beforeStateChange();        // as the first stage's forces would
    }
    graph->launched = true;
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

// The step's launches captured into graph.exec; false (graphs then off for this backend, the error
// cleared) where the driver refused the capture: nothing of the step was launched.
template <class Real>
bool CudaDevice<Real>::captureRkStep(RkGraph& graph, int stages, double dt) {
    cudaStream_t s = stream();
    const int window = m_timingWindow;
    m_timingWindow = -1;  // no per-pass timing events inside the graph: the pair around its launch brackets it
    const int64_t evaluations = m_allPairsEvaluations, passes = m_fullPasses;
    const bool snapshot = m_snapshotPending;  // taken inside: pending again if the capture fails
    graph.exec = captureGraph(s, [&] { Backend::rkStep(stages, dt); });
    const bool made = graph.exec != nullptr;
    m_timingWindow = window;
    graph.evaluations = m_allPairsEvaluations - evaluations;
    graph.passes = m_fullPasses - passes;
    m_allPairsEvaluations = evaluations;  // counted where the graph is launched
    m_fullPasses = passes;
    if (made) return true;
    graph.reset();
    m_rkGraphsOff = true;
    m_snapshotPending = snapshot;
    return false;
}

template <class Real>
void CudaDevice<Real>::RkGraph::reset() {
    if (exec) cudaGraphExecDestroy(exec);
    exec = nullptr;
    key = RkGraphKey{};
    evaluations = passes = 0;
    launched = false;
}

template class CudaDevice<float>;
template class CudaDevice<double>;

}  // namespace corebox
