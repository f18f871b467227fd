// The one-call API: zeroreg::Register(source, target, config).
//
//   zeroreg::Scan source = zeroreg::LoadScan("../shared/data/7scenes-redkitchen@20");
//   zeroreg::Scan target = zeroreg::LoadScan("../shared/data/7scenes-redkitchen@0");
//   zeroreg::RegistrationResult r = zeroreg::Register(source, target);
//   if (r.valid) use(r.T_target_source); else log(r.reason);
//
// For many pairs, build one Pipeline (it loads the models once) and call Register repeatedly.
#pragma once

#include <memory>

#include "zeroreg/config.hpp"
#include "zeroreg/types.hpp"

namespace zeroreg {

class Pipeline {
 public:
  // Resolves and verifies the model files and loads them. Throws InputError on a bad config or a
  // missing/corrupt model.
  explicit Pipeline(const PipelineConfig& config);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Throws InputError when a scan cannot be used at all (no views, empty or mismatched images).
  // A registration that fails is returned with valid = false and a reason, never as a silent
  // identity.
  RegistrationResult Register(const Scan& source, const Scan& target) const;

  const PipelineConfig& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

RegistrationResult Register(const Scan& source, const Scan& target,
                            const PipelineConfig& config = PipelineConfig());

}  // namespace zeroreg
