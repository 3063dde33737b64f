"""`Ros2Swarm`: the agent side of shoal's ROS 2 bridge for a set of vehicles, on Cyclone DDS.

One DDS participant with, per vehicle ``<v>`` of a world run by ``shoal run`` whose group says
``agent = "ros2"``, readers of ``/<namespace>/<v>/imu``, ``…/pressure``, ``…/modem/rx``,
``…/modem/outcome`` (and ``…/odom`` when asked for) and writers of ``…/setpoint``, ``…/actuators`` and ``…/modem/tx``
(DDS topics ``rt/<namespace>/<v>/<topic>``; ``<v>`` is the vehicle's name made a ROS 2 name,
`ros_name`: ``auv-0`` → ``auv_0``), plus a reader of ``/clock``. Vehicles are named as in the
run's trajectories.csv throughout the API::

    from shoal_ros2 import Ros2Swarm, Setpoint

    with Ros2Swarm("shoal", ["auv-0", "auv-1"], domain_id=7) as swarm:
        while (tick := swarm.wait_tick(timeout=5.0)) is not None:
            for v, o in tick.observations.items():
                swarm.send_setpoint(v, tick.stamp, Setpoint.MODE_AUTO, 1.5, o.yaw + 0.1)

A *tick* is complete when every vehicle's ``imu`` and ``pressure`` (and ``odom``) with one
stamp T have arrived, in whatever order the topics deliver them; answering each vehicle with a
``Setpoint`` or ``Actuators`` stamped T (after the ``modem/tx`` frames it counts) is what a
lock-step world waits for. Observations are converted back to shoal's frames (NED world, FRD
body, :mod:`shoal_ros2.enu`); the ROS messages stay available on each observation.
"""

import math
import os
import time
from dataclasses import dataclass, field
from typing import Dict, Iterable, Iterator, List, Optional, Sequence, Tuple, Union

from cyclonedds.core import (
    DDSException,
    InstanceState,
    ReadCondition,
    SampleState,
    ViewState,
    WaitSet,
)
from cyclonedds.domain import Domain, DomainParticipant
from cyclonedds.pub import DataWriter, Publisher
from cyclonedds.sub import DataReader, Subscriber
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from . import enu, qos
from .msgs import (
    Actuators,
    Clock,
    FluidPressure,
    FrameOutcome,
    Imu,
    Odometry,
    OpticalFrame,
    Setpoint,
    Time,
)

__all__ = [
    "LOCALHOST_CONFIG",
    "NotMatched",
    "Observation",
    "Ros2Swarm",
    "Tick",
    "dds_topic",
    "localhost_only_from_env",
    "ros_name",
]

#: A stamp as a dictionary key: (sec, nanosec).
_Key = Tuple[int, int]
#: Incomplete ticks kept at most (older ones are dropped).
_MAX_PENDING = 256
#: Longest single wait on the wait set [s]: the deadline is checked at least this often.
_WAIT_SLICE_S = 0.1


#: Cyclone DDS configuration that keeps discovery and data on this machine: the loopback
#: interface, unicast only, peers found at 127.0.0.1 (up to 20 participants per domain). Use it
#: as ``CYCLONEDDS_URI`` for other Cyclone DDS programs too.
LOCALHOST_CONFIG = (
    "<CycloneDDS><Domain id=\"any\"><General><Interfaces>"
    "<NetworkInterface address=\"127.0.0.1\"/></Interfaces>"
    "<AllowMulticast>false</AllowMulticast></General>"
    "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
    "<MaxAutoParticipantIndex>20</MaxAutoParticipantIndex>"
    "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery></Domain></CycloneDDS>"
)


def localhost_only_from_env() -> bool:
    """Whether ROS 2's environment asks for discovery on this machine only:
    ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`` (ROS 2 Iron and later) or
    ``ROS_LOCALHOST_ONLY=1`` (before)."""
    return (os.environ.get("ROS_AUTOMATIC_DISCOVERY_RANGE", "").upper() == "LOCALHOST"
            or os.environ.get("ROS_LOCALHOST_ONLY") == "1")


class NotMatched(RuntimeError):
    """A command writer found no subscriber (no world with this namespace, vehicle and
    domain) within `Ros2Swarm.match_timeout`."""


def ros_name(vehicle: str) -> str:
    """A vehicle's name (as in trajectories.csv) as the bridge puts it into topic names and
    frame ids, a ROS 2 name: every character but ASCII letters and digits becomes ``_``, runs
    of ``_`` one ``_``, none at the end, and a leading digit gets a ``v`` before it
    (``school-0`` → ``school_0``, ``x--y`` → ``x_y``, ``3d`` → ``v3d``) — the rule of
    ``crates/shoal-ros2/src/names.rs`` (``ros_name``). A ROS name comes out as itself."""
    out = []
    for c in vehicle:
        c = c if c.isascii() and c.isalnum() else "_"
        if not (c == "_" and (not out or out[-1] == "_")):
            out.append(c)
    s = "".join(out).rstrip("_")
    if not s or s[0].isdigit():
        s = "v" + s
    return s


def dds_topic(namespace: str, vehicle: Optional[str], leaf: str) -> str:
    """The DDS topic name of the ROS topic ``/<namespace>/<vehicle>/<leaf>`` (ROS 2 prefixes
    ``rt``), `vehicle` being a ROS name (`ros_name`); with `vehicle` None, of the global
    ``/<leaf>`` (``/clock``, ``/tf``)."""
    if vehicle is None:
        return f"rt/{leaf}"
    ns = namespace.strip("/")
    return f"rt/{ns}/{vehicle}/{leaf}" if ns else f"rt/{vehicle}/{leaf}"


@dataclass
class Observation:
    """One vehicle at one control tick, as its ROS topics reported it, in shoal's frames."""

    #: The vehicle's name (as in the run's trajectories.csv).
    vehicle: str
    #: Its index in the `Ros2Swarm`'s vehicle list.
    index: int
    #: Simulated time of the tick [s].
    time: float
    #: Depth from the pressure reading [m, positive down].
    depth: float
    #: IMU roll [rad] (shoal's FRD body in NED).
    roll: float
    #: IMU pitch [rad], nose up positive.
    pitch: float
    #: IMU heading [rad], −π … π, 0 north, π/2 east.
    yaw: float
    #: Gyro rates (p, q, r) in the FRD body frame [rad/s].
    rates: Tuple[float, float, float]
    #: Accelerometer specific force in the FRD body frame [m/s²].
    accel: Tuple[float, float, float]
    #: True position (north, east, down) of the body origin [m] from ``odom``, or None.
    position: Optional[Tuple[float, float, float]]
    #: Frames received on ``modem/rx`` since the previous tick, in order of arrival.
    frames: List[OpticalFrame]
    #: What became of the vehicle's acknowledged unicasts (``modem/outcome``) since the
    #: previous tick, in order of arrival.
    outcomes: List[FrameOutcome]
    #: The ROS messages themselves.
    imu: Imu
    pressure: FluidPressure
    odom: Optional[Odometry] = None


@dataclass
class Tick:
    """A complete control tick: every vehicle's observation with one stamp."""

    #: The tick's stamp (simulated time); answer with exactly this one.
    stamp: Time
    #: The same in seconds [s].
    time: float
    #: Per vehicle name, in the `Ros2Swarm`'s order.
    observations: Dict[str, Observation] = field(default_factory=dict)


class _Vehicle:
    """One vehicle's readers and writers."""

    def __init__(self, swarm: "Ros2Swarm", name: str, index: int) -> None:
        self.name = name
        self.index = index
        r, w, ros = swarm._reader, swarm._writer, ros_name(name)
        self.imu = r(Imu, ros, "imu", qos.SENSOR_DATA)
        self.pressure = r(FluidPressure, ros, "pressure", qos.SENSOR_DATA)
        self.odom = r(Odometry, ros, "odom", qos.SENSOR_DATA) if swarm.odometry else None
        self.rx = r(OpticalFrame, ros, "modem/rx", qos.RECEIVED_FRAMES)
        self.outcome = r(FrameOutcome, ros, "modem/outcome", qos.RECEIVED_FRAMES)
        self.setpoint = w(Setpoint, ros, "setpoint")
        self.actuators = w(Actuators, ros, "actuators")
        self.tx = w(OpticalFrame, ros, "modem/tx")

    def sensors(self) -> Iterable[Tuple[int, DataReader]]:
        """(slot, reader) of the topics a tick needs: 0 imu, 1 pressure, 2 odom."""
        yield 0, self.imu
        yield 1, self.pressure
        if self.odom is not None:
            yield 2, self.odom


class Ros2Swarm:
    """The agent side of the ROS 2 bridge for `vehicles` of the world publishing under
    `namespace` on DDS domain `domain_id` (the world's ``[ros2]`` table).

    `odometry`: also read ``odom`` (published only with ``[agents] grant_position = true``);
    `odom_grace` [s, wall time]: how long a tick otherwise complete waits for it. `density`
    [kg/m³] and `gravity` [m/s²]: the world's, for depth from pressure. `match_timeout` [s,
    wall time]: how long the first command to a topic waits for the world's subscriber (a
    sample written before DDS discovery matched it is lost).
    `localhost_only`: keep DDS on this machine (`LOCALHOST_CONFIG`); None: as ROS 2's
    environment says (`localhost_only_from_env`). It configures the domain when this process
    has none of that id yet; otherwise the domain's configuration (``CYCLONEDDS_URI``) stays.

    Use it as a context manager or call `close`.
    """

    def __init__(
        self,
        namespace: str = "shoal",
        vehicles: Sequence[str] = (),
        domain_id: int = 0,
        *,
        odometry: bool = False,
        density: float = enu.WATER_DENSITY,
        gravity: float = enu.GRAVITY,
        match_timeout: float = 5.0,
        odom_grace: float = 0.02,
        localhost_only: Optional[bool] = None,
    ) -> None:
        names = list(vehicles)
        if not names:
            raise ValueError("Ros2Swarm needs at least one vehicle name")
        if len({ros_name(n) for n in names}) != len(names):
            raise ValueError(f"two of the vehicles {names} have the same ROS 2 name")
        if not 0 <= domain_id <= 232:
            raise ValueError(f"domain_id {domain_id}: ROS 2 domains are 0 … 232")
        #: The namespace without slashes at either end.
        self.namespace = namespace.strip("/")
        #: The vehicle names, in order.
        self.vehicles = names
        self.domain_id = domain_id
        self.odometry = odometry
        self.density = density
        self.gravity = gravity
        self.match_timeout = match_timeout
        self.odom_grace = odom_grace
        self._topics: Dict[str, Topic] = {}
        self._matched = set()
        if localhost_only is None:
            localhost_only = localhost_only_from_env()
        self._domain = None
        if localhost_only:
            try:
                self._domain = Domain(domain_id, LOCALHOST_CONFIG)
            except DDSException:
                pass  # this process has the domain already, configured as it is
        self._participant = DomainParticipant(domain_id)
        self._subscriber = Subscriber(self._participant)
        self._publisher = Publisher(self._participant)
        self._v: Dict[str, _Vehicle] = {n: _Vehicle(self, n, i) for i, n in enumerate(names)}
        self._clock = self._reader(Clock, None, "clock", qos.SENSOR_DATA)
        self._waitset = WaitSet(self._participant)
        self._conditions = []
        mask = SampleState.NotRead | ViewState.Any | InstanceState.Any
        for veh in self._v.values():
            for _, reader in veh.sensors():
                cond = ReadCondition(reader, mask)
                self._waitset.attach(cond)
                self._conditions.append(cond)
        #: Observations of incomplete ticks: stamp → vehicle → [imu, pressure, odom].
        self._pending: Dict[_Key, Dict[str, list]] = {}
        #: The newest tick returned by `wait_tick` (older stamps are ignored).
        self._last: Optional[_Key] = None
        #: Newest /clock time seen [s].
        self._clock_s: Optional[float] = None

    @classmethod
    def for_world(cls, path, **kwargs) -> "Ros2Swarm":
        """A swarm of every vehicle of the world file `path` with ``agent = "ros2"``, on its
        ``[ros2]`` domain and namespace, with its water density and, when it grants positions,
        odometry (:class:`shoal_ros2.world.Ros2World`); `kwargs` go to the constructor."""
        from .world import Ros2World

        w = Ros2World.load(path)
        if not w.vehicles:
            raise ValueError(f"{path}: no vehicle group says agent = \"ros2\"")
        kwargs.setdefault("odometry", w.odometry)
        kwargs.setdefault("density", w.density)
        return cls(w.namespace, w.vehicles, w.domain_id, **kwargs)

    # Entities --------------------------------------------------------------------------------

    def _topic(self, cls, vehicle: Optional[str], leaf: str) -> Topic:
        name = dds_topic(self.namespace, vehicle, leaf)
        if name not in self._topics:
            self._topics[name] = Topic(self._participant, name, cls)
        return self._topics[name]

    def _reader(self, cls, vehicle: Optional[str], leaf: str, profile) -> DataReader:
        return DataReader(self._subscriber, self._topic(cls, vehicle, leaf), qos=profile)

    def _writer(self, cls, vehicle: str, leaf: str) -> DataWriter:
        return DataWriter(self._publisher, self._topic(cls, vehicle, leaf), qos=qos.COMMANDS)

    def __enter__(self) -> "Ros2Swarm":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Deletes the participant and everything in it (idempotent): the entities go with
        their last references, held only here, and Cyclone DDS tells the world at once."""
        for attr in ("_conditions", "_waitset", "_v", "_clock", "_topics", "_subscriber",
                     "_publisher", "_participant", "_domain"):
            self.__dict__.pop(attr, None)

    def _vehicle(self, name: str) -> _Vehicle:
        try:
            return self._v[name]
        except KeyError:
            raise KeyError(f"vehicle `{name}` is not one of {self.vehicles}") from None
        except AttributeError:
            raise RuntimeError("the Ros2Swarm is closed") from None

    # Observations ----------------------------------------------------------------------------

    def _drain(self) -> None:
        """Takes every queued sensor sample into `_pending`."""
        for v in self._v.values():
            for slot, reader in v.sensors():
                for s in reader.take(N=256):
                    if not hasattr(s, "header"):
                        continue  # an invalid sample (e.g. the world's writer went away)
                    key = (s.header.stamp.sec, s.header.stamp.nanosec)
                    if self._last is not None and key <= self._last:
                        continue
                    self._pending.setdefault(key, {}).setdefault(v.name, [None] * 3)[slot] = s
        while len(self._pending) > _MAX_PENDING:
            del self._pending[min(self._pending)]

    def _complete(self, slots: int) -> Optional[_Key]:
        """The newest stamp of which every vehicle has its first `slots` sensor samples (2:
        imu and pressure; 3: and odom), or None."""
        done = [
            k for k, per in self._pending.items()
            if len(per) == len(self._v)
            and all(all(x is not None for x in got[:slots]) for got in per.values())
        ]
        return max(done) if done else None

    def wait_tick(self, timeout: float) -> Optional[Tick]:
        """Waits up to `timeout` [s, wall time] for a complete tick — every vehicle's ``imu``
        and ``pressure`` with one stamp — and returns the newest one (older ones are dropped:
        in lock-step there is only one, a free-running world may have moved on); None after
        `timeout`. With `odometry`, it also waits up to `odom_grace` [s] for the tick's
        ``odom`` (not part of what a lock-step world promises: a vehicle whose odom has not
        come by then has ``position`` None). Each observation carries the ``modem/rx`` frames
        and ``modem/outcome`` events that had arrived by then."""
        deadline = time.monotonic() + timeout
        grace: Optional[Tuple[_Key, float]] = None  # a tick waiting for odom, until when
        while True:
            self._drain()
            key = self._complete(2)
            if key is not None:
                if not self.odometry or self._complete(3) == key:
                    return self._tick(key)
                if grace is None or grace[0] != key:
                    grace = (key, time.monotonic() + self.odom_grace)
                if time.monotonic() >= grace[1]:
                    return self._tick(key)
            left = (grace[1] if grace else deadline) - time.monotonic()
            if time.monotonic() >= deadline and grace is None:
                return None
            self._waitset.wait(duration(seconds=max(0.0, min(left, _WAIT_SLICE_S))))

    def ticks(self, wait: float = 60.0, idle: float = 10.0) -> Iterator[Tick]:
        """Yields complete ticks (`wait_tick`) until none comes for `idle` [s, wall time] —
        the run ended, or the world stalled — waiting up to `wait` [s] for the first one."""
        timeout = wait
        while (tick := self.wait_tick(timeout)) is not None:
            timeout = idle
            yield tick

    def _tick(self, key: _Key) -> Tick:
        per = self._pending[key]
        for k in [k for k in self._pending if k <= key]:
            del self._pending[k]
        self._last = key
        stamp = Time(sec=key[0], nanosec=key[1])
        t = enu.seconds(stamp)
        tick = Tick(stamp=stamp, time=t)
        for name, v in self._v.items():
            imu, pressure, odom = per[name]  # odom None without it (or after the grace)
            roll, pitch, yaw = enu.attitude_to_ned(imu.orientation)
            tick.observations[name] = Observation(
                vehicle=name,
                index=v.index,
                time=t,
                depth=enu.depth_from_pressure(pressure.fluid_pressure, self.density, self.gravity),
                roll=roll,
                pitch=pitch,
                yaw=yaw,
                rates=enu.frd(imu.angular_velocity),
                accel=enu.frd(imu.linear_acceleration),
                position=enu.position_to_ned(odom.pose.pose.position) if odom else None,
                frames=self.received(name),
                outcomes=self.outcomes(name),
                imu=imu,
                pressure=pressure,
                odom=odom,
            )
        return tick

    def received(self, vehicle: str) -> List[OpticalFrame]:
        """The frames `vehicle` received (``modem/rx``) not yet returned, in order of arrival.
        Each: ``stamp`` end of reception, ``sender`` (the sending vehicle's ROS name,
        `ros_name`), ``to`` (`vehicle`'s ROS name for a unicast to it, '' for a broadcast),
        ``seq``, ``modem`` index, ``power`` [W], ``snr`` [-], ``payload`` (list of byte values;
        ``bytes(f.payload)``)."""
        return [s for s in self._vehicle(vehicle).rx.take(N=1000) if hasattr(s, "payload")]

    def outcomes(self, vehicle: str) -> List[FrameOutcome]:
        """What became of `vehicle`'s frames sent with ``ack`` (``modem/outcome``) not yet
        returned, in order of arrival. Each: ``stamp`` when it ended, ``to`` (the destination's
        ROS name), ``tag``, ``seq``, ``transmissions``, ``acknowledged``, ``sent``."""
        return [s for s in self._vehicle(vehicle).outcome.take(N=1000)
                if hasattr(s, "acknowledged")]

    def clock(self) -> Optional[float]:
        """The newest simulated time published on ``/clock`` so far [s], or None."""
        for s in self._clock.take(N=256):
            if hasattr(s, "clock"):
                t = enu.seconds(s.clock)
                if self._clock_s is None or t > self._clock_s:
                    self._clock_s = t
        return self._clock_s

    # Commands --------------------------------------------------------------------------------

    def _write(self, writer: DataWriter, sample) -> None:
        if id(writer) not in self._matched:
            deadline = time.monotonic() + self.match_timeout
            while not writer.get_matched_subscriptions():
                if time.monotonic() >= deadline:
                    raise NotMatched(
                        f"no subscriber of {writer.topic.name} on domain {self.domain_id} "
                        f"within {self.match_timeout} s: is `shoal run` running a world with "
                        f"`agent = \"ros2\"` and this namespace?"
                    )
                time.sleep(0.005)
            self._matched.add(id(writer))
        writer.write(sample)

    def send_setpoint(
        self,
        vehicle: str,
        stamp: Union[Time, float],
        mode: int,
        depth: float,
        heading: float,
        surge: float = 0.0,
        sway: float = 0.0,
        frames: int = 0,
    ) -> None:
        """Answers tick `stamp` (a ``Time`` or seconds [s]) for `vehicle` with controller mode
        `mode` (``Setpoint.MODE_*``), `depth` [m, positive down], `heading` [rad, shoal's NED:
        0 north, π/2 east], `surge` and `sway` forces [N]; `frames`: the ``modem/tx`` frames
        stamped `stamp` sent for it before this (`send_frame`)."""
        msg = Setpoint(stamp=_time(stamp), mode=mode, depth=depth, heading=heading,
                       surge=surge, sway=sway, frames=frames)
        self._write(self._vehicle(vehicle).setpoint, msg)

    def send_actuators(
        self,
        vehicle: str,
        stamp: Union[Time, float],
        thrusters: Sequence[float],
        tilts: Sequence[float] = (),
        pump: int = 0,
        frames: int = 0,
    ) -> None:
        """Answers tick `stamp` for `vehicle` with raw commands: `thrusters` [% of full scale]
        and `tilts` [rad] in the vehicle file's order, `pump` −1 empty / 0 off / +1 fill;
        `frames` as for `send_setpoint`."""
        msg = Actuators(stamp=_time(stamp), thrusters=[float(x) for x in thrusters],
                        tilts=[float(x) for x in tilts], pump=pump, frames=frames)
        self._write(self._vehicle(vehicle).actuators, msg)

    def send_frame(
        self,
        vehicle: str,
        stamp: Union[Time, float],
        payload: bytes,
        modem: int = OpticalFrame.ALL_MODEMS,
        delay: float = 0.0,
        to: Optional[str] = None,
        ack: bool = False,
        tag: int = 0,
    ) -> None:
        """Sends `payload` (at most the modem's payload size [bytes]) from `vehicle`'s modem
        `modem` (an index, or ``OpticalFrame.ALL_MODEMS`` for all at once), `delay` [s] after
        tick `stamp`: a broadcast, or with `to` (a vehicle of the world, named as in
        trajectories.csv or by its ROS name: it is sent as `ros_name(to)`) a unicast; with `ack`
        too, acknowledged and retransmitted until it is, and what became of it comes back in
        `outcomes` with `tag` (0 … 2³² − 1). A destination that is no vehicle's, the sender
        itself, or `ack` without `to` make it a bad frame (counted by the world, not sent). In
        lock-step count it in the tick's Setpoint or Actuators `frames`."""
        msg = OpticalFrame(stamp=_time(stamp), to=ros_name(to) if to else "", ack=bool(ack),
                           tag=tag, modem=modem, delay=delay, payload=bytes(payload))
        self._write(self._vehicle(vehicle).tx, msg)


def _time(stamp: Union[Time, float]) -> Time:
    if isinstance(stamp, Time):
        return stamp
    if not (isinstance(stamp, (int, float)) and math.isfinite(stamp) and stamp >= 0):
        raise ValueError(f"stamp {stamp!r}: a Time or seconds ≥ 0")
    return enu.stamp(float(stamp))
