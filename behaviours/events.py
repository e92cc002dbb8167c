"""The one vocabulary of what the behaviours report to the episode log.

Each kind carries the one-line reading a person needs to understand it; the log refuses
any other kind, and ``csl log``, the plots and ``docs/executive.md`` take the list from
here, so a new event is added in one place.
"""

from __future__ import annotations

from enum import Enum


class Event(str, Enum):
    """One kind of episode-log event, with its reading and whether it is a recovery."""

    reading: str
    recovery: bool

    def __new__(cls, value: str, reading: str, recovery: bool = False) -> Event:
        member = str.__new__(cls, value)
        member._value_ = value
        member.reading = reading
        member.recovery = recovery
        return member

    def __str__(self) -> str:
        return self.value

    LOCATED = "located", ("the object regions a look found (centroid, pixels, orientation), nearest first: the "
                          "overhead camera's, or the candidates the onboard scans tracked")
    VIEW = "view", ("exploring without a ceiling camera: a scan taken where the robot stands (pose, candidates so "
                    "far) and the next view to look from, or none when the home is mapped")
    EXPLORE_MOVE = "explore_move", ("exploring: the robot drove to the next view (seconds, whether it collided, "
                                    "the pose it ended at); or `unreachable` and why")
    MAPPED = "mapped", ("exploration ended (views, robot seconds, candidates found); `reason` says why: the home "
                        "is mapped, the views' bound was spent, or no view can be reached from where the robot "
                        "stands")
    OBJECT = "object", ("work starts on an object: where it lies and where the robot stands relative to it "
                        "(`cluster: true` when vision saw touching objects as one region)")
    CHOOSE = "choose", "a test chosen (how: best, reselect or backtrack), its position, gain, move and sensing seconds"
    MOVE = "move", "the robot drove to a position: seconds, whether it collided, the pose it ended at"
    BUMPED = "bumped", ("a move stopped collided where the map saw nothing (a table's top above the scan plane): "
                        "the place it met, kept out of the plans from now on")
    SENSE = "sense", "a sensing procedure applied: the values it yielded and its seconds"
    BRANCH = "branch", "the measured value matched a branch of the run-time tree (value and range)"
    UNRELIABLE = "unreliable", "the value fell between or beyond the branches (or none came): not trusted"
    BACKTRACK = "backtrack", "the parent's value invalidated to choose a different test there (depth)", True
    NEAREST = "nearest", "the branch nearest an unreliable value followed, the last resort", True
    CHOOSE_GRASP = "choose_grasp", "a grasp chosen at a leaf, or an ambiguous leaf's grasp tried as a feature"
    GRASP = "grasp", "a grasp executed (at a leaf or as a feature) and whether the fingers hold"
    SIDE_EFFECT = "side_effect", "what the camera saw after a failed grasp: pushed, changed or none"
    START_OVER = "start_over", "a failed grasp had side effects: every description restored, start again", True
    DROP_GRASP = "drop_grasp", "a grasp failed cleanly: its descriptions dropped, the tree rebuilt from here", True
    GRASP_FEATURE_FAILED = "grasp_feature_failed", "a grasp tried as a feature failed: its 'failure' branch followed"
    DISCRIMINATE = "discriminate", "after a wrong prediction, a feature measured to tell the object apart", True
    LEAVE = "leave", "a grasp the finger sensor cannot confirm (No-Grab): the object is left where it is"
    LEARN = "learn", ("the new object description saved (id, grasp, features, wrong predictions; `by: appearance` "
                      "when nothing was sensed and it is stored by its appearance), or `id: null` and the `reason` "
                      "nothing was stored (docs/method.md §5.3)")
    REST_OF_CLUSTER = "rest_of_cluster", "a cluster's grasped object put away: what the camera sees left of it, queued next", True
    GAVE_UP = "gave_up", "the object is reported failed (every grasp failed, or its step budget was spent)"
    DRIVER_ERROR = "driver_error", "the driver refused or failed a verb (code and message)"
    DRIVER_FAULT = "driver_fault", ("an `internal` or malformed reply: the driver failed, not the test (verb, "
                                    "message); counted, and the run ends non-zero")
    IMPLAUSIBLE = "implausible", ("a sensed value outside its feature's span or far outside every library "
                                  "description (feature, value, why): the test is unusable here, reselected"), True
    GRASP_UNVERIFIED = "grasp_unverified", ("a grasp reported held, yet the camera still sees the object on the "
                                            "floor: the object fails, nothing is learned, the driver is suspect")
    GRASP_COST_IGNORED = "grasp_cost_ignored", ("a grasp's duration implausible against its procedure's time "
                                                "(grasp, seconds, expected): not counted in learned grasp costs")
    REAPPROACH = "reapproach", ("the driver refused a procedure as out of range: nothing was tried; the robot "
                                "re-approaches its position and tries again (procedure, tries)"), True
    NO_PATH = "no_path", "no collision-free path to a position: unusable there", True
    BEAM_BLOCKED = "beam_blocked", "a test's sonar beam would meet another object (neighbours' centroids): unusable there", True
    OTHER_END = "other_end", "a grasp position with no path approached from the object's other end", True
    CHARGE = "charge", "the battery ran low: the robot drove to its dock and charged (levels, seconds), then resumed"
    LOCALISED = "localised", ("the overhead camera (or the onboard scan matcher) placed the robot away from where "
                              "its dead reckoning said (seen, was): its poses corrected by the offset (and turn) "
                              "from now on")
    DISTURBANCE = "disturbance", "the camera check before a sensing or grasp: the object moved, changed or gone"
    RELOCATE = "relocate", "the object was moved: followed to its new place, every value measured kept", True
    START_AFRESH = "start_afresh", "another object where ours was: started over on it, nothing kept", True
    GONE = "gone", "the object was taken away: reported gone (not a failure), on to the next one"
    EPISODE_END = "episode_end", "the tree finished (status, ticks)"


RECOVERIES = frozenset(e.value for e in Event if e.recovery)  # as logged: plain strings
