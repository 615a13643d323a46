"""vlpground: Velodyne VLP-16 decoding and ground detection from Python.

Read a capture frame by frame::

    import vlpground
    for frame in vlpground.read_pcap("pcaps/urban_demo.pcap"):
        pts = frame.to_numpy_points()          # N x 11 float64, valid returns
        ground = frame.xyz[frame.label == 1]   # M x 3 float32

Frames are 16 x N range images (rows = rings, 0 = lowest beam; columns = firing sequences).
Per-cell arrays are read-only numpy views over the frame's memory with its row stride (no
copy); ``xyz``, ``ring``, ``laser``, ``time_s``, ``time_ns`` and ``to_numpy_points()`` are one
copy each. Decoding and detection run in C++ with the GIL released. See docs/python.md.
"""
from __future__ import annotations

import os
from typing import Iterable, Mapping, Optional, Sequence, Union

from ._core import (  # noqa: F401  (re-exported)
    POINT_FIELDS,
    SCENES,
    DetectorConfig,
    Extrinsics,
    Frame,
    FrameLayer,
    FrameMeta,
    FrameReader,
    GpsState,
    GroundDetector,
    GroundSegment,
    Plane,
    sim_extrinsics,
)
from . import _core

__all__ = [
    "POINT_FIELDS", "SCENES", "DetectorConfig", "Extrinsics", "Frame", "FrameLayer",
    "FrameMeta", "FrameReader", "GpsState", "GroundDetector", "GroundSegment", "Plane",
    "read_pcap", "count_frames", "live", "evaluate", "simulate", "sim_extrinsics",
]
__version__: str = _core.__version__  # the CMake project version

PathLike = Union[str, "os.PathLike[str]"]
ExtrinsicsLike = Union[Extrinsics, Sequence[float], Mapping[str, float], None]


def _extrinsics(value: ExtrinsicsLike) -> Optional[Extrinsics]:
    """Extrinsics from an Extrinsics, (x, y, z, roll, pitch, yaw) or a dict of its fields."""
    if value is None or isinstance(value, Extrinsics):
        return value
    if isinstance(value, Mapping):
        return Extrinsics(**value)
    values = [float(v) for v in value]
    if len(values) != 6:
        raise ValueError("extrinsics expects (x_m, y_m, z_m, roll_deg, pitch_deg, yaw_deg), "
                         f"got {len(values)} numbers")
    names = ("x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg")
    return Extrinsics(**dict(zip(names, values)))


class _DefaultMethod(str):
    """The default `method` argument: "tangent", unless a `detector` config says otherwise."""


DEFAULT_METHOD = _DefaultMethod("tangent")


def _detector(method: Optional[str], extrinsics: ExtrinsicsLike,
              detector: Optional[DetectorConfig]) -> DetectorConfig:
    """One DetectorConfig from the keyword shortcuts and an optional full config (an
    explicit `method` or `extrinsics` overrides the config's)."""
    config = DetectorConfig(**{name: getattr(detector, name) for name in _CONFIG_FIELDS}) \
        if detector is not None else DetectorConfig()
    if method is not None and not (detector is not None and isinstance(method, _DefaultMethod)):
        config.method = method
    pose = _extrinsics(extrinsics)
    if pose is not None:
        config.extrinsics = pose
    config.validate()
    return config


_CONFIG_FIELDS = [name for name in dir(DetectorConfig)
                  if not name.startswith("_") and name != "validate"]


def _frames_limit(frames: Optional[int]) -> int:
    if frames is None:
        return 0
    if frames < 1:
        raise ValueError(f"frames must be >= 1 or None, got {frames}")
    return int(frames)


def read_pcap(path: PathLike, *, method: str = DEFAULT_METHOD,
              extrinsics: ExtrinsicsLike = None, calibration: Optional[PathLike] = None,
              model: Optional[str] = None, cut_angle_deg: float = 0.0,
              sensor_ip: Optional[str] = None, port: int = 2368, position_port: int = 8308,
              detector: Optional[DetectorConfig] = None, frames: Optional[int] = None,
              loop: bool = False, first_frame: int = 0) -> FrameReader:
    """Frames of a pcap/pcapng capture, decoded and labelled, in capture order.

    Args:
        path: the capture (Ethernet/VLAN, Linux SLL/SLL2, raw IP, loopback; IPv4/IPv6).
        method: ground method, "tangent" (the paper's, default), "ransac" or "lpr".
        extrinsics: sensor pose in the vehicle, an Extrinsics, (x, y, z, roll, pitch, yaw)
            in metres and degrees, or a dict of Extrinsics fields. None: identity.
        calibration: ROS velodyne calibration YAML (default: built-in angles).
        model: "vlp16" or "hires" to decode as this model whatever the product byte says.
        cut_angle_deg: azimuth where frames start.
        sensor_ip: only packets from this address (default: any).
        port, position_port: UDP ports of data and position packets in the capture.
        detector: full DetectorConfig; `method` and `extrinsics`, when given, override its
            fields.
        frames: stop after this many frames (default: all).
        loop: replay the file again at its end, joined as one continuous recording
            (timestamps keep increasing; frames stay full rotations across the seam).
        first_frame: start at the frame of this sequence number; the frames before it are
            decoded (frames are cut where the whole capture is cut) but not labelled or
            returned, so consecutive ranges of a capture never lose or double a frame.

    The first and last frames of a capture are usually partial rotations
    (``frame.meta.complete`` is False), exactly as the CLI delivers them. Raises
    RuntimeError when the file is missing or not a capture, and at the end when no frame
    was decoded (no VLP-16 data packets: another sensor, other ports, truncated, empty).
    """
    return _core._open_pcap(os.fspath(path), _detector(method, extrinsics, detector),
                            os.fspath(calibration) if calibration else "", model,
                            float(cut_angle_deg), sensor_ip or "", int(port),
                            int(position_port), bool(loop), _frames_limit(frames),
                            _first_frame(first_frame))


def count_frames(path: PathLike, **read_options) -> int:
    """The number of frames ``read_pcap(path, **read_options)`` yields, without ground
    detection (decoding alone: about 1000x real time)."""
    return read_pcap(path, **read_options).skip_to_end()


def _first_frame(first_frame: int) -> int:
    if first_frame < 0:
        raise ValueError(f"first_frame must be >= 0, got {first_frame}")
    return int(first_frame)


def live(port: int = 2368, bind: str = "0.0.0.0", *, position_port: int = 8308,
         sensor_ip: Optional[str] = None, multicast: Optional[str] = None,
         reuse_address: bool = False, method: str = DEFAULT_METHOD,
         extrinsics: ExtrinsicsLike = None, calibration: Optional[PathLike] = None,
         model: Optional[str] = None, cut_angle_deg: float = 0.0,
         detector: Optional[DetectorConfig] = None, frames: Optional[int] = None,
         duration_s: Optional[float] = None, timeout_s: Optional[float] = None) -> FrameReader:
    """Frames from a live sensor on UDP, until stopped.

    The iteration ends after ``frames`` frames or ``duration_s`` seconds, when
    ``reader.stop()`` is called (from any thread), or with KeyboardInterrupt on Ctrl-C (the
    wait for packets is sliced into 0.1 s steps that check for signals, so a notebook cell
    stops promptly). ``timeout_s``: raise TimeoutError when no frame arrived for that long.
    ``position_port=0`` does not listen for position packets (no GPS state).

    Frames are read in the caller's thread: while Python is busy with a frame the packets
    wait in the socket's receive buffer (4 MiB requested, about 2.5 s at 10 Hz); beyond that
    the kernel drops them (``reader.counters["source"]["kernel_drops"]``).
    Raises RuntimeError when the port is in use or the address is not on this host.
    """
    return _core._open_live(int(port), bind, int(position_port), sensor_ip or "",
                            multicast or "", bool(reuse_address),
                            _detector(method, extrinsics, detector),
                            os.fspath(calibration) if calibration else "", model,
                            float(cut_angle_deg), _frames_limit(frames),
                            float(duration_s or 0.0), float(timeout_s or 0.0))


def evaluate(pcap: PathLike, labels: PathLike, *, method: str = DEFAULT_METHOD,
             radius_m: float = 40.0, extrinsics: ExtrinsicsLike = None,
             detector: Optional[DetectorConfig] = None,
             frames: Optional[int] = None) -> dict:
    """Precision, recall and F1 of ground detection against a ``.labels`` ground truth.

    The same figures, computed by the same evaluation library, as
    ``vlpground eval PCAP --labels LABELS --json``: capture, method, radius_m, frames,
    precision, recall, f1, tp, fp, fn, tn, detect_ms_total, high_obstacle_as_ground_rate,
    high_obstacles, high_obstacles_as_ground and high_obstacle_terrain (``"exact"`` when the
    simulator's ``.heights`` file lies beside the labels, else ``"estimated"``; ``"none"``
    without obstacles). As the CLI, a simulator capture's mounting pose is read from
    STEM.json beside it unless ``extrinsics`` is given.
    """
    config = _detector(method, extrinsics, detector)
    return _core._evaluate(os.fspath(pcap), os.fspath(labels), config,
                           _extrinsics(extrinsics) is not None, float(radius_m),
                           _frames_limit(frames))


def simulate(scene: str, out: PathLike, *, seed: int = 1, frames: int = 10, rpm: float = 600.0,
             mode: str = "strongest", model: str = "vlp16",
             sensor_height_m: Optional[float] = None, speed_mps: Optional[float] = None,
             roll_deg: float = 0.0, pitch_deg: float = 0.0) -> dict:
    """Writes a labelled synthetic capture OUT.pcap, OUT.labels, OUT.heights and OUT.json.

    ``scene`` is one of SCENES (flat, urban, slope, hills, jam, fences); the rest as
    ``vlpground sim``. Returns the paths and a summary (data_packets, position_packets,
    returns, ground_returns, duration_s).
    """
    return _core._simulate(scene, os.fspath(out), int(seed), int(frames), float(rpm), mode,
                           model, sensor_height_m, speed_mps, float(roll_deg), float(pitch_deg))
