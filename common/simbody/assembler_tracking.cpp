// GCC 12 reports a false -Warray-bounds inside Simbody's own OrientationSensors header (its inline
// defineObservationOrder builds Rotation().setRotationToNaN()); the code is Simbody's, not ours.
#pragma GCC diagnostic ignored "-Warray-bounds"

#include "common/assembler_tracking.h"

#include <cmath>
#include <string>

#include "common/simbody/model_impl.h"

namespace syn {

struct AssemblerTracker::Impl {
  const Model::Impl& model;
  std::vector<AssemblerTask> tasks;
  SimTK::Assembler assembler;
  SimTK::Markers* markers = nullptr;               // owned by the assembler
  SimTK::OrientationSensors* sensors = nullptr;    // owned by the assembler
  SimTK::State state;
  SimTK::Array_<SimTK::Vec3> marker_observations;
  SimTK::Array_<SimTK::Rotation> sensor_observations;
  bool started = false;

  Impl(const Model::Impl& model_in, std::vector<AssemblerTask> tasks_in, double accuracy)
      : model(model_in), tasks(std::move(tasks_in)), assembler(model_in.system), state(model_in.system.getDefaultState()) {
    model.system.realizeModel(state);
    assembler.setAccuracy(accuracy);
    auto* new_markers = new SimTK::Markers();
    auto* new_sensors = new SimTK::OrientationSensors();
    for (size_t i = 0; i < tasks.size(); ++i) {
      const LinkPlacement& placement = model.links[static_cast<size_t>(tasks[i].link)];
      const std::string name = "task" + std::to_string(i);
      if (tasks[i].position) {
        const Eigen::Vector3d origin = placement.in_body.translation();
        new_markers->addMarker(name, placement.body, SimTK::Vec3(origin.x(), origin.y(), origin.z()), tasks[i].weight);
      }
      if (tasks[i].orientation) {
        new_sensors->addOSensor(name, placement.body, ToSimbodyRotation(placement.in_body.linear()), tasks[i].weight);
      }
    }
    // Observations arrive in the order the markers and sensors were added.
    new_markers->defineObservationOrder(SimTK::Array_<SimTK::Markers::MarkerIx>());
    new_sensors->defineObservationOrder(SimTK::Array_<SimTK::OrientationSensors::OSensorIx>());
    marker_observations.resize(new_markers->getNumMarkers());
    sensor_observations.resize(new_sensors->getNumOSensors());
    if (new_markers->getNumMarkers() > 0) {
      assembler.adoptAssemblyGoal(new_markers);
      markers = new_markers;
    } else {
      delete new_markers;
    }
    if (new_sensors->getNumOSensors() > 0) {
      assembler.adoptAssemblyGoal(new_sensors);
      sensors = new_sensors;
    } else {
      delete new_sensors;
    }
    // Joint limits as the Assembler's restricted ranges (OpenSim passes clamped coordinates the same way).
    const int q_offset = model.floating_base == FloatingBase::kFree ? 1 : 0;
    for (size_t b = 0; b < model.mobilities.size(); ++b) {
      const Model::Impl::Mobility& mobility = model.mobilities[b];
      if (mobility.kind != Model::Impl::MobilityKind::kPin && mobility.kind != Model::Impl::MobilityKind::kSlider) continue;
      const int q = mobility.u_index + q_offset;
      const double lower = model.q_lower[q], upper = model.q_upper[q];
      if (std::isfinite(lower) && std::isfinite(upper) && lower < upper) {
        assembler.restrictQ(SimTK::MobilizedBodyIndex(static_cast<int>(b)), SimTK::MobilizerQIndex(0), lower, upper);
      }
    }
  }
};

AssemblerTracker::AssemblerTracker(const Model& model, const std::vector<AssemblerTask>& tasks, double accuracy)
    : impl_(std::make_unique<Impl>(model.impl(), tasks, accuracy)) {}

AssemblerTracker::~AssemblerTracker() = default;

void AssemblerTracker::track(const std::vector<Eigen::Vector3d>& positions,
                             const std::vector<Eigen::Quaterniond>& orientations, Eigen::VectorXd& q) {
  Impl& impl = *impl_;
  int marker = 0, sensor = 0;
  for (size_t i = 0; i < impl.tasks.size(); ++i) {
    if (impl.tasks[i].position) {
      const Eigen::Vector3d& p = positions[i];
      impl.marker_observations[static_cast<unsigned>(marker++)] = SimTK::Vec3(p.x(), p.y(), p.z());
    }
    if (impl.tasks[i].orientation) {
      impl.sensor_observations[static_cast<unsigned>(sensor++)] = ToSimbodyRotation(orientations[i].toRotationMatrix());
    }
  }
  if (impl.markers) impl.markers->moveAllObservations(impl.marker_observations);
  if (impl.sensors) impl.sensors->moveAllObservations(impl.sensor_observations);
  if (!impl.started) {
    for (int i = 0; i < impl.model.nq; ++i) impl.state.updQ()[i] = q[i];
    impl.assembler.initialize(impl.state);
    impl.assembler.assemble();
    impl.started = true;
  } else {
    impl.assembler.track();
  }
  impl.assembler.updateFromInternalState(impl.state);
  q.resize(impl.model.nq);
  for (int i = 0; i < impl.model.nq; ++i) q[i] = impl.state.getQ()[i];
}

}  // namespace syn
