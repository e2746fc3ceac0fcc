// The lists of validate's checks, in the order they run and print. A new check: its file in
// this folder; here, its accessor declared and put in its list.
#include "validation/checks/check.h"

namespace oct {

const RunCheck& filmCheck();           // film_check.cpp
const RunCheck& structureCheck();      // structure_check.cpp
const RunCheck& rayCheck();            // ray_check.cpp
const SceneCheck& replicationCheck();  // replication_check.cpp
const SceneCheck& boxContractCheck();  // box_contract_check.cpp
const SceneCheck& cameraCheck();       // camera_check.cpp
const SceneCheck& shadowRayCheck();    // shadow_ray_check.cpp
const SceneCheck& rayScalingCheck();   // ray_scaling_check.cpp

const std::vector<const RunCheck*>& runChecks() {
    static const std::vector<const RunCheck*> list = {&filmCheck(), &structureCheck(), &rayCheck()};
    return list;
}

const std::vector<const SceneCheck*>& sceneChecks() {
    static const std::vector<const SceneCheck*> list = {&replicationCheck(), &boxContractCheck(),
                                                        &cameraCheck(), &shadowRayCheck(),
                                                        &rayScalingCheck()};
    return list;
}

}  // namespace oct
