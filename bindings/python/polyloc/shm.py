"""polyloc.shm: the shared-memory client of polylocd (docs/interface.md, docs/python.md).

From the extension (``polyloc._polyloc._shm``, over service/shm):

- :class:`Segment`: ``Segment.attach(instance)`` maps polylocd's segment ``/dev/shm/polyloc.<instance>``;
  ``Segment.create(instance, channels)`` makes one (tests, simulations, a stand-in daemon);
  ``generation``, ``state``, ``stale()``, ``reattach()``, ``channels()``;
- :class:`Writer`: one channel's writer (``write_ranges``, ``write_depth``, ``write_odometry``, and
  ``write_pose``, ``write_vrs``, ``write_tracks``, ``write_health`` for the outputs);
- :class:`Reader`: ``next()`` / ``newest()`` give frames as dicts (or None), ``wait(timeout_s)``
  sleeps with the GIL released, ``overruns`` counts frames lost by falling behind;
- :func:`daemon_channels`: polylocd's channel table for a config;
- errors: :class:`ShmError` (a RuntimeError) and its kinds SegmentNotFoundError (also a
  FileNotFoundError), AbiError, NotReadyError, BusyError, ShmValueError (also a ValueError).

Written in Python: :func:`attach` (waits for a starting polylocd), :class:`SimFeed` (a simulation's
odometry and frames into the input channels, as a robot's drivers would write them) and
:func:`play` (a :class:`polyloc.SimRun` fed at real time, moved onto the wall clock).
"""

from __future__ import annotations

import time
from typing import Callable, Dict, Optional

from ._polyloc import _shm

ABI_VERSION = _shm.ABI_VERSION
ShmError = _shm.ShmError
SegmentNotFoundError = _shm.SegmentNotFoundError
AbiError = _shm.AbiError
NotReadyError = _shm.NotReadyError
BusyError = _shm.BusyError
ShmValueError = _shm.ShmValueError
Segment = _shm.Segment
Writer = _shm.Writer
Reader = _shm.Reader
daemon_channels = _shm.daemon_channels


def attach(instance: str, timeout: float = 0.0, poll: float = 0.05) -> Segment:
    """Segment.attach, retried while the segment does not exist yet or is being created.

    timeout: seconds to keep trying (0: once); then the last error is raised as it was.
    """
    deadline = time.monotonic() + timeout
    while True:
        try:
            return Segment.attach(instance)
        except (SegmentNotFoundError, NotReadyError):
            if time.monotonic() >= deadline:
                raise
        time.sleep(poll)


class SimFeed:
    """A simulation's odometry and sensor frames into polylocd's input channels.

    The routing of polylocd's channel table (:func:`daemon_channels`): a scanner or lidar of the
    rig goes to ``scan/<sensor>``, a depth camera to ``depth/<sensor>`` (the simulated ranges
    along the pixel rays turned into depth along the optical axis), odometry to ``odom``.
    ``sent`` counts the frames written per channel; frames of sensors the segment has no
    channel for are counted in ``skipped``.
    """

    def __init__(self, segment: Segment, rig, take_over: bool = False):
        self.segment = segment
        self.rig = rig
        self.take_over = take_over
        self.sent: Dict[str, int] = {}
        self.skipped: Dict[str, int] = {}
        self._writers: Dict[str, Writer] = {}
        self._routes: Dict[int, tuple] = {}

    def _writer(self, channel: str) -> Writer:
        w = self._writers.get(channel)
        if w is None:
            w = self._writers[channel] = Writer(self.segment, channel, take_over=self.take_over)
        return w

    def _route(self, sensor: int) -> tuple:
        route = self._routes.get(sensor)
        if route is None:
            s = self.rig[sensor]
            if s.kind == "depth_camera":
                spec = s.spec
                route = ("depth/" + s.name, spec.depth_factors().reshape(spec.height, spec.width))
            else:
                route = ("scan/" + s.name, None)
            self._routes[sensor] = route
        return route

    def odometry(self, stamp_ns: int, odom_T_base, twist=(0.0, 0.0, 0.0)) -> None:
        """One odometry tick (cumulative odom_T_base)."""
        self._writer("odom").write_odometry(stamp_ns, odom_T_base, twist)
        self.sent["odom"] = self.sent.get("odom", 0) + 1

    def frame(self, frame, stamp_ns: Optional[int] = None) -> None:
        """One SimFrame, stamped stamp_ns (default: its own stamp)."""
        channel, factors = self._route(frame.sensor)
        if channel not in self.segment:
            self.skipped[channel] = self.skipped.get(channel, 0) + 1
            return
        stamp = frame.stamp_ns if stamp_ns is None else stamp_ns
        if factors is None:
            self._writer(channel).write_ranges(stamp, frame.measured)
        else:
            self._writer(channel).write_depth(stamp, frame.measured.reshape(factors.shape) * factors)
        self.sent[channel] = self.sent.get(channel, 0) + 1

    def close(self) -> None:
        """Releases the writer roles."""
        for w in self._writers.values():
            w.close()
        self._writers.clear()


def play(segment: Segment, run, rate: float = 1.0, on_event: Optional[Callable[[int], None]] = None,
         feed: Optional[SimFeed] = None) -> SimFeed:
    """Feed a :class:`polyloc.SimRun` into a segment at ``rate`` x real time, in time order.

    Stamps are moved onto the wall clock (CLOCK_REALTIME; what polylocd's ``clock: wall``
    expects): stamp - the run's first + the time of the start, divided by ``rate``. Every event
    waits for its time; ``on_event(wall_stamp_ns)`` is called after each (read outputs there).
    Returns the feed (its ``sent`` counts; its ``shift_ns`` maps the run's stamps onto the
    wall clock, its ``start_ns`` is the start).
    """
    feed = feed or SimFeed(segment, run.rig)
    first = run.stamps[0] if run.stamps else (run.frames[0].stamp_ns if run.frames else 0)
    start = time.time_ns()
    feed.start_ns, feed.rate = start, rate
    feed.shift_ns = start - first
    for kind, stamp, item in run.events():
        wall = start + int((stamp - first) / rate)
        delay = (wall - time.time_ns()) / 1e9
        if delay > 0:
            time.sleep(delay)
        if kind == "odometry":
            feed.odometry(wall, item)
        else:
            feed.frame(item, wall)
        if on_event is not None:
            on_event(wall)
    return feed


__all__ = ["ABI_VERSION", "ShmError", "SegmentNotFoundError", "AbiError", "NotReadyError", "BusyError",
           "ShmValueError", "Segment", "Writer", "Reader", "daemon_channels", "attach", "SimFeed", "play"]
