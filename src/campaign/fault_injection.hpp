#pragma once
// A test hook, off unless the environment sets it: TUMBLE_TEST_FAULT="<case id>:<rank>:<step>"
// makes one particle owned by rank <rank> of case <case id>'s group leave the tumbler at the first
// health check (every 1000 steps) at or after <step>. The CI test of rank groups
// (tests/campaign/groups_check.py) uses it to check that a failure seen by one rank of a group is
// recorded with that rank's diagnostic while the other groups go on, and that nothing hangs.
#include <memory>
#include <string>

#include "run/observer.hpp"

namespace tumble::campaign {

// The observer for this case if the hook names it, else nullptr.
std::unique_ptr<Observer> fault_injection_for(const std::string& case_id);

}  // namespace tumble::campaign
