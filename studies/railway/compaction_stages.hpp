#pragma once
// The stages between the trimming and the settling (bed_preparation.hpp, steps 4b-5c): radius
// expansion, tamping, consolidation and traffic. Each takes the bed as the stage before left it
// and leaves it for the next; `settle` holds the design friction and local damping and the
// sleeper as the settling releases it.
#include "studies/railway/bed_preparation.hpp"
#include "studies/railway/preparation_stage.hpp"

namespace mfdem::railway {

StageReport run_expansion(const PushStudyConfig& config, const StageSetup& settle, const PreparationControl& control,
                          BedBetweenStages& bed);
StageReport run_tamping(const PushStudyConfig& config, const StageSetup& settle, const PreparationControl& control,
                        BedBetweenStages& bed);
StageReport run_consolidation(const PushStudyConfig& config, const StageSetup& settle,
                              const PreparationControl& control, BedBetweenStages& bed);
StageReport run_traffic(const PushStudyConfig& config, const StageSetup& settle, const PreparationControl& control,
                        BedBetweenStages& bed);

// The downward load on the sleeper t (s) into the traffic stage, N: traffic_load sin^2(pi t /
// traffic_period), zero between pulses.
double traffic_load_at(const PreparationSettings& preparation, double t);

}  // namespace mfdem::railway
