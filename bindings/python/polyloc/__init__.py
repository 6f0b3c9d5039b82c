"""polyloc: polygon-map localisation, ray casting, simulation and depth filtering for mobile robots.

The C++ kernels over numpy arrays (float32 for rays and ranges, float64 for poses), from the
extension module ``polyloc._polyloc``, plus a few helpers written in Python:

- :func:`simulate` runs a scenario and collects its odometry ticks and sensor frames,
- :class:`SimRun` holds them and replays them in time order (:meth:`SimRun.events`),
- :func:`replay` feeds a run into a :class:`Localizer` and pairs each estimate with the truth,
- :func:`settings_dict` turns a settings struct (MclConfig, DepthFilterConfig, ...) into a dict.

The submodule :mod:`polyloc.shm` is the shared-memory client of polylocd (segments, channel
writers and readers; docs/interface.md).

Errors: FileNotFoundError for missing files; MapError and RecordingError (OSError) for files that
cannot be read; ConfigError (ValueError) naming file, line and key; ValueError for wrong array
shapes or values, TypeError for arrays that are not numeric. docs/python.md has an overview.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from typing import Iterator, List, Optional, Tuple, Union

from . import _polyloc
from ._polyloc import *  # noqa: F401,F403  (the kernels)
from ._polyloc import (Estimate, Localizer, Pose, Rig, Scenario, SimFrame, Simulator,
                       load_scenario)
from . import shm  # noqa: E402  (the Python module polyloc.shm over _polyloc._shm)


@dataclass
class SimRun:
    """A simulated run collected by :func:`simulate`.

    ``stamps`` are the odometry ticks (int64 ns), ``truth`` and ``odometry`` the map_T_base and
    odom_T_base poses at each tick; ``frames`` every sensor frame in time order.
    """

    rig: Rig
    duration: float
    stamps: List[int] = field(default_factory=list)
    truth: List[Pose] = field(default_factory=list)
    odometry: List[Pose] = field(default_factory=list)
    frames: List[SimFrame] = field(default_factory=list)
    summary: dict = field(default_factory=dict)

    def events(self) -> Iterator[Tuple[str, int, Union[Pose, SimFrame]]]:
        """("odometry", stamp_ns, odom_T_base) and ("scan", stamp_ns, frame) in time order.

        At equal stamps odometry comes first, so a scan finds the odometry of its own time.
        """
        i = j = 0
        while i < len(self.stamps) or j < len(self.frames):
            if j == len(self.frames) or (i < len(self.stamps) and self.stamps[i] <= self.frames[j].stamp_ns):
                yield "odometry", self.stamps[i], self.odometry[i]
                i += 1
            else:
                yield "scan", self.frames[j].stamp_ns, self.frames[j]
                j += 1

    def truth_at(self, stamp_ns: int) -> Pose:
        """Ground truth at a stamp, interpolated between the odometry ticks."""
        k = bisect.bisect_left(self.stamps, stamp_ns)
        if k == 0:
            return self.truth[0]
        if k == len(self.stamps):
            return self.truth[-1]
        t0, t1 = self.stamps[k - 1], self.stamps[k]
        return Pose.interpolate(self.truth[k - 1], self.truth[k], (stamp_ns - t0) / (t1 - t0))


def simulate(scenario: Union[str, Scenario], duration: Optional[float] = None, seed: Optional[int] = None,
             out: str = "", sensors: Optional[List[str]] = None) -> SimRun:
    """Run a scenario (a path or a :class:`Scenario`) and collect ticks and frames.

    duration shortens the run (s), seed replaces the scenario's, out also writes a recording
    ('*.mcap' or a ROS 2 bag directory), sensors keeps only the frames of these rig sensors.
    """
    if isinstance(scenario, str):
        scenario = load_scenario(scenario, duration=duration, seed=seed)
    else:
        if duration is not None:
            scenario.duration = float(duration)
        if seed is not None:
            scenario.seed = int(seed)
    sim = Simulator(scenario)
    run = SimRun(rig=sim.rig, duration=sim.duration)
    keep = None
    if sensors is not None:
        keep = {run.rig.find(name) for name in sensors}
        if -1 in keep:
            raise ValueError(f"simulate: sensors {sensors} not all in rig '{run.rig.name}' ({run.rig.names})")

    def on_tick(stamp: int, truth: Pose, odom: Pose) -> None:
        run.stamps.append(stamp)
        run.truth.append(truth)
        run.odometry.append(odom)

    def on_frame(frame: SimFrame) -> None:
        if keep is None or frame.sensor in keep:
            run.frames.append(frame)

    run.summary = sim.run(out, on_frame=on_frame, on_tick=on_tick)
    return run


def replay(localizer: Localizer, run: SimRun, start: Optional[Pose] = None,
           covariance=None) -> List[Tuple[Estimate, Pose]]:
    """Feed a run's odometry and frames to a localiser; (estimate, true pose) after every update.

    The filter starts at ``start`` (default: the first true pose) with ``covariance`` (default:
    Localizer.init_pose's); pass ``start=False`` for a localiser already initialised.
    """
    if start is not False:
        localizer.init_pose(run.truth[0] if start is None else start, covariance, run.stamps[0])
    out = []
    for kind, stamp, item in run.events():
        if kind == "odometry":
            localizer.add_odometry(stamp, item)
        elif localizer.add_scan(item.sensor, stamp, item.measured):
            estimate = localizer.estimate()
            out.append((estimate, run.truth_at(estimate.stamp_ns)))
    return out


def settings_dict(settings) -> dict:
    """A settings struct (MclConfig, DepthFilterConfig, ...) as a nested dict of its fields."""
    out = {}
    for name in dir(type(settings)):
        attr = getattr(type(settings), name)
        if name.startswith("_") or not isinstance(attr, property):
            continue
        value = getattr(settings, name)
        out[name] = settings_dict(value) if type(value).__module__.startswith("polyloc") else value
    return out


__all__ = [n for n in dir(_polyloc) if not n.startswith("_")] + ["SimRun", "simulate", "replay", "settings_dict"]
