#pragma once
// Temporary files being written (NAME.tmp.<pid>, renamed over NAME when complete), removed if a
// terminating signal ends the process while they are open: `tumble cm manifolds` killed with
// SIGTERM while it wrote left its temporary behind, up to gigabytes. SIGKILL cannot be caught:
// after it a temporary may stay (the final name is never damaged; the temporary is safe to
// delete).
#include <string>

namespace tumble {

// Records a temporary file in a fixed table of slots (best effort: a path too long for a slot, or
// no slot free, is not recorded). Not for signal handlers.
void register_temporary(const std::string& path);
// Forgets it (renamed into place, or removed).
void forget_temporary(const std::string& path);
// Removes every recorded temporary; async-signal-safe (unlink only).
void remove_temporaries_now();
// Installs, for SIGTERM, SIGINT and SIGHUP, a handler that removes them and then ends the process
// with the signal's default action. `tumble run` and `tumble campaign` replace it for SIGTERM and
// SIGINT with their stop handlers (stop_request.hpp), which end the process at once only on a
// second signal, and remove the temporaries then.
void remove_temporaries_on_signal();

}  // namespace tumble
