#include "vocabulary.h"

namespace corebox {
namespace {

// The order of each table is the order of every list a user sees (help, messages, the panel).
constexpr Term<Method> kMethods[] = {
    {Method::Euler, "euler", "order 1"},
    {Method::Rk2, "rk2", "order 2"},
    {Method::Rk4, "rk4", "order 4"},
    {Method::Dp5, "dp5", "order 5"},
    {Method::Hairer10, "hairer10", "order 10"},
    {Method::Verlet, "verlet", "order 2, symplectic"},
    {Method::ForestRuth, "forest_ruth", "order 4, symplectic"},
    {Method::Pefrl, "pefrl", "order 4, symplectic"},
    {Method::BlanesMoan, "blanes_moan", "order 4, symplectic"},
    {Method::Yoshida6, "yoshida6", "order 6, symplectic"},
    {Method::Yoshida8, "yoshida8", "order 8, symplectic"},
};
constexpr Term<Precision> kPrecisions[] = {{Precision::Fp32, "fp32", ""}, {Precision::Fp64, "fp64", ""}};
constexpr Term<BackendKind> kBackends[] = {
    {BackendKind::Cpu, "cpu", ""}, {BackendKind::Cuda, "cuda", ""}, {BackendKind::Auto, "auto", "cuda when a GPU is present, else cpu"}};
constexpr Term<ThermostatKind> kThermostats[] = {
    {ThermostatKind::Bussi, "bussi", ""}, {ThermostatKind::Rescale, "rescale", ""}, {ThermostatKind::None, "none", ""}};
constexpr Term<CutoffShift> kShifts[] = {
    {CutoffShift::None, "none", ""}, {CutoffShift::Energy, "energy", ""}, {CutoffShift::Force, "force", ""}};
constexpr Term<Placement> kPlacements[] = {{Placement::Lattice, "lattice", ""}, {Placement::Random, "random", ""}};
constexpr Term<Exchange> kExchanges[] = {{Exchange::Auto, "auto", "the fastest measured"},
                                         {Exchange::Dts, "dts", "synchronous peer copies"},
                                         {Exchange::Dta, "dta", "asynchronous peer copies"},
                                         {Exchange::Da, "da", "direct access to peer memory"},
                                         {Exchange::Nccl, "nccl", "NCCL all-gather"}};
constexpr Term<ForceModel> kForceModels[] = {{ForceModel::Auto, "auto", "the cheapest that serves the scene"},
                                             {ForceModel::AllPairs, "all_pairs", "every pair, the report's model"},
                                             {ForceModel::NeighbourList, "neighbour_list", "Verlet lists within the cutoff"}};

constexpr Vocabulary<Method> kMethodTable("method", kMethods);
constexpr Vocabulary<Precision> kPrecisionTable("precision", kPrecisions);
constexpr Vocabulary<BackendKind> kBackendTable("backend", kBackends);
constexpr Vocabulary<ThermostatKind> kThermostatTable("thermostat kind", kThermostats);
constexpr Vocabulary<CutoffShift> kShiftTable("shift", kShifts);
constexpr Vocabulary<Placement> kPlacementTable("placement", kPlacements);
constexpr Vocabulary<Exchange> kExchangeTable("exchange", kExchanges);
constexpr Vocabulary<ForceModel> kForceModelTable("forces", kForceModels);

}  // namespace

const Vocabulary<Method>& methodTable() { return kMethodTable; }
const Vocabulary<Precision>& precisionTable() { return kPrecisionTable; }
const Vocabulary<BackendKind>& backendTable() { return kBackendTable; }
const Vocabulary<ThermostatKind>& thermostatTable() { return kThermostatTable; }
const Vocabulary<CutoffShift>& shiftTable() { return kShiftTable; }
const Vocabulary<Placement>& placementTable() { return kPlacementTable; }
const Vocabulary<Exchange>& exchangeTable() { return kExchangeTable; }
const Vocabulary<ForceModel>& forceModelTable() { return kForceModelTable; }

const char* methodName(Method method) { return methodTable().name(method); }
bool parseMethod(const std::string& text, Method* method) { return methodTable().parse(text, method); }
const char* precisionName(Precision precision) { return precisionTable().name(precision); }
const char* thermostatName(ThermostatKind kind) { return thermostatTable().name(kind); }
const char* shiftName(CutoffShift shift) { return shiftTable().name(shift); }
const char* exchangeName(Exchange exchange) { return exchangeTable().name(exchange); }

const char* forceModelName(ForceModel model) { return model == ForceModel::None ? "none" : kForceModelTable.name(model); }

}  // namespace corebox
