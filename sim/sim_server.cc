#include "sim/sim_server.h"

#include <chrono>

namespace ts::sim {

Result<std::unique_ptr<SimServer>> SimServer::Start(std::shared_ptr<const SimStation> station,
                                                    const SimServeOptions& options) {
  std::unique_ptr<SimServer> server(new SimServer());
  server->options_ = options;
  SimulatedStageOptions stage;
  stage.levelling = station->rig.truth.stage;
  stage.inclinometer_index_error_deg = station->rig.inclinometer_index_error_deg;
  stage.inclinometer_noise_deg = station->rig.inclinometer_noise_deg;
  stage.seed = station->scene.seed;
  stage.corrupt_reply_ratio = options.faults.modbus_crc;
  stage.drop_reply_ratio = options.faults.modbus_drop;
  if (const auto& f = options.faults.stage_stall)
    (f->pan ? stage.pan : stage.tilt).stall_after_moves = f->after_moves;
  if (const auto& f = options.faults.stage_alarm)
    (f->pan ? stage.pan : stage.tilt).alarm_after_moves = f->after_moves;
  server->stage_ = std::make_unique<SimulatedStage>(stage);
  if (Status s = server->stage_->ListenTcp(options.stage_address, options.stage_port); !s)
    return Error{s.error()};
  if (options.stage_pty) {
    Result<std::string> pty = server->stage_->ServePty();
    if (!pty) return Error{pty.error()};
    server->pty_path_ = *pty;
  }
  SimulatedStage* stage_ptr = server->stage_.get();
  auto pose = [stage_ptr] { return stage_ptr->Pose(); };
  SimulatedCameraOptions cameras[2];
  cameras[1].side = Side::kRight;
  ServeCalibrationTargets(station->rig, station->scene.seed, options.calibration, &cameras[0],
                          &cameras[1]);
  for (Side side : {Side::kLeft, Side::kRight}) {
    SimulatedCameraOptions& camera = cameras[side == Side::kLeft ? 0 : 1];
    camera.address = side == Side::kLeft ? options.left_address : options.right_address;
    camera.serial = side == Side::kLeft ? options.left_serial : options.right_serial;
    camera.gvsp_loss_ratio = options.faults.gvsp_loss;
    camera.hidden_address =
        side == Side::kLeft ? options.left_hidden_address : options.right_hidden_address;
    camera.render = options.render;
    auto& slot = side == Side::kLeft ? server->left_ : server->right_;
    slot = std::make_unique<SimulatedCamera>(station, pose, camera);
    if (Status s = slot->Start(); !s) return Error{s.error()};
  }
  SimulatedCamera* left = server->left_.get();
  SimulatedCamera* right = server->right_.get();
  std::vector<StagePose> resting;
  for (const StagePose& target : options.prerender_targets)
    resting.push_back(server->stage_->RestingPose(target));
  std::thread right_prerender([&] { right->Prerender(resting); });
  left->Prerender(resting);
  right_prerender.join();
  server->stage_->SetOnMoveStarted([left, right](const StagePose& p) {
    left->RenderAhead(p);
    right->RenderAhead(p);
  });
  server->stage_->SetViewReady(
      [left, right](const StagePose& p) { return left->HasView(p) && right->HasView(p); });
  if (options.faults.camera_gone) {
    const CameraGoneFault fault = *options.faults.camera_gone;
    SimServer* self = server.get();
    server->fault_thread_ = std::thread([self, fault] { self->CameraGoneLoop(fault); });
  }
  return server;
}

SimServer::~SimServer() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
  }
  quit_changed_.notify_all();
  if (fault_thread_.joinable()) fault_thread_.join();
  // The stage's physics thread calls into the cameras (render ahead, view ready): stopped
  // before they go; their threads read its pose until then, so it goes last.
  if (stage_) stage_->Stop();
  left_.reset();
  right_.reset();
  stage_.reset();
}

void SimServer::CameraGoneLoop(CameraGoneFault fault) {
  using std::chrono::duration;
  std::unique_lock lock(mutex_);
  if (quit_changed_.wait_for(lock, duration<double>(fault.after_s), [&] { return quit_; })) return;
  camera(fault.side).Stop();
  if (quit_changed_.wait_for(lock, duration<double>(fault.for_s), [&] { return quit_; })) return;
  (void)camera(fault.side).Start();  // back on the network; a failure leaves it gone
}

std::vector<StagePose> DesignPlanTargets(const SimStation& station) {
  return MakeCapturePlan(DesignCalibration(station.scene.stage_height_m), CapturePlanOptions{});
}

nlohmann::json SimServer::Endpoints() const {
  nlohmann::json j = {
      {"left_camera", {{"address", options_.left_address}, {"serial", options_.left_serial}}},
      {"right_camera", {{"address", options_.right_address}, {"serial", options_.right_serial}}},
      {"stage_tcp", options_.stage_address + ":" + std::to_string(options_.stage_port)},
      {"stage_unit_id", 1}};
  if (!pty_path_.empty()) j["stage_rtu"] = pty_path_;
  return j;
}

}  // namespace ts::sim
