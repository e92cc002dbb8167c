"""The learner service: one shared library of object descriptions and its learning.

Decisions are computed next to each robot (they need its move costs and take
milliseconds); what robots share is the *library*. ``LocalLearner`` keeps it in
process on SQLite; ``zenoh_node`` serves any service over zenoh and ``zenoh_client``
reaches one, so several robots learn into one library; ``outbox`` keeps what a robot
learned until the service has it (docs/reliability.md). The zenoh modules are not
imported here: an in-process learner should not pay for loading zenoh.
"""

from learner.service.interface import LearnerService, LibrarySnapshot
from learner.service.local import LocalLearner

__all__ = ["LearnerService", "LibrarySnapshot", "LocalLearner"]
