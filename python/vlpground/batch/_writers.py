"""Per-capture label files, written frame by frame (memory stays flat on long captures).

Every format holds one row per valid return, in the order of the CLI's ``--csv``:
frame, laser_id, ring, return, time, azimuth_deg, distance_m, x, y, z, intensity and the
label. Files are written under a temporary name and renamed when complete, so a file with
the final name is always whole.
"""
from __future__ import annotations

import io
import os
import zipfile
from pathlib import Path

import numpy as np

HOUR_NS = 3_600_000_000_000
FORMATS = ("npz", "csv", "parquet")

# Column name -> dtype of the npz and parquet outputs.
COLUMNS = {
    "frame": np.uint32, "laser_id": np.uint8, "ring": np.uint8, "return": np.uint8,
    "time_ns": np.int64, "azimuth_deg": np.float32, "distance_m": np.float32,
    "x": np.float32, "y": np.float32, "z": np.float32, "intensity": np.uint8,
    "label": np.uint8,
}
_FIELDS = ["laser", "ring", "return", "azimuth_deg", "range_m", "x", "y", "z", "intensity",
           "label", "column"]
FIRING_NS = 2304  # laser k fires 2.304 us after laser k-1
CSV_HEADER = ("frame,laser_id,ring,return,timestamp_us,azimuth_deg,distance_m,x,y,z,"
              "intensity,ground")


def parquet_available() -> bool:
    try:
        import pyarrow  # noqa: F401
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        return False
    return True


def check_format(fmt: str) -> None:
    if fmt not in FORMATS:
        raise ValueError(f"format must be one of {', '.join(FORMATS)}, got {fmt!r}")
    if fmt == "parquet" and not parquet_available():
        raise ValueError(
            "format='parquet' needs pyarrow, which is not installed (Debian 12 has no "
            "python3-pyarrow package); use format='npz' or 'csv', or install pyarrow")


def frame_columns(frame) -> dict:
    """The returns of one frame as typed columns (CSV order)."""
    pts = frame.to_numpy_points(_FIELDS)
    # Exact firing times (int64 ns): the column's time plus the laser's firing offset.
    laser = pts[:, 0].astype(np.int64)
    time_ns = frame.column_time_ns[pts[:, 10].astype(np.intp)] + laser * FIRING_NS
    cols = {
        "frame": np.full(len(pts), frame.meta.sequence), "laser_id": pts[:, 0],
        "ring": pts[:, 1], "return": pts[:, 2], "time_ns": time_ns,
        "azimuth_deg": pts[:, 3], "distance_m": pts[:, 4], "x": pts[:, 5], "y": pts[:, 6],
        "z": pts[:, 7], "intensity": pts[:, 8], "label": pts[:, 9],
    }
    return {name: np.asarray(values).astype(COLUMNS[name], copy=False)
            for name, values in cols.items()}


class CsvWriter:
    """The CLI's --csv format, byte for byte (same header, columns and decimals)."""

    suffix = ".csv"

    def __init__(self, path: Path):
        self._file = open(path, "w", newline="")
        self._file.write(CSV_HEADER + "\n")

    def write(self, frame) -> None:
        c = frame_columns(frame)
        past_hour = c["time_ns"] % HOUR_NS
        ground = (c["label"] == 1).astype(np.uint8)
        table = np.column_stack([
            c["frame"], c["laser_id"], c["ring"], c["return"], past_hour // 1000,
            past_hour % 1000]).astype(np.int64)
        floats = np.column_stack([c["azimuth_deg"], c["distance_m"], c["x"], c["y"], c["z"]]
                                 ).astype(np.float64)
        out = io.StringIO()
        for ints, f, inten, g in zip(table.tolist(), floats.tolist(), c["intensity"].tolist(),
                                     ground.tolist()):
            out.write("%d,%d,%d,%d,%d.%03d,%.3f,%.3f,%.4f,%.4f,%.4f,%d,%d\n"
                      % (*ints, *f, inten, g))
        self._file.write(out.getvalue())

    def append_part(self, part: Path) -> None:
        """Appends the rows of a file this writer made (its header skipped)."""
        with open(part, newline="") as f:
            f.readline()
            while chunk := f.read(1 << 20):
                self._file.write(chunk)

    def close(self) -> None:
        self._file.close()


class NpzWriter:
    """One .npz with a flat array per column (COLUMNS). Columns are streamed to raw files
    frame by frame and packed into the archive at the end, so memory does not grow with the
    capture's length."""

    suffix = ".npz"

    def __init__(self, path: Path):
        self._path = path
        self._raw = {name: open(f"{path}.{name}.raw", "wb") for name in COLUMNS}
        self._rows = 0

    def write(self, frame) -> None:
        self.write_columns(frame_columns(frame))

    def write_columns(self, cols: dict) -> None:
        for name, dtype in COLUMNS.items():
            self._raw[name].write(np.ascontiguousarray(cols[name], dtype=dtype).tobytes())
        self._rows += len(cols["frame"])

    def append_part(self, part: Path) -> None:
        self.write_columns(read_npz(part))

    def close(self) -> None:
        for f in self._raw.values():
            f.close()
        with zipfile.ZipFile(self._path, "w", zipfile.ZIP_STORED, allowZip64=True) as archive:
            for name, dtype in COLUMNS.items():
                raw = f"{self._path}.{name}.raw"
                header = {"descr": np.lib.format.dtype_to_descr(np.dtype(dtype)),
                          "fortran_order": False, "shape": (self._rows,)}
                with archive.open(f"{name}.npy", "w", force_zip64=True) as member:
                    np.lib.format.write_array_header_2_0(member, header)
                    with open(raw, "rb") as src:
                        while chunk := src.read(1 << 20):
                            member.write(chunk)
                os.remove(raw)


class ParquetWriter:
    """Parquet (pyarrow), one row group per frame."""

    suffix = ".parquet"

    def __init__(self, path: Path):
        import pyarrow as pa
        import pyarrow.parquet as pq
        self._pa = pa
        schema = pa.schema([(n, pa.from_numpy_dtype(np.dtype(t))) for n, t in COLUMNS.items()])
        self._writer = pq.ParquetWriter(str(path), schema)

    def write(self, frame) -> None:
        self._writer.write_table(self._pa.table(frame_columns(frame)))

    def append_part(self, part: Path) -> None:
        import pyarrow.parquet as pq
        source = pq.ParquetFile(str(part))
        for group in range(source.num_row_groups):
            self._writer.write_table(source.read_row_group(group))

    def close(self) -> None:
        self._writer.close()


WRITERS = {"csv": CsvWriter, "npz": NpzWriter, "parquet": ParquetWriter}


def read_npz(path) -> dict:
    """The columns of a label file written as npz."""
    with np.load(path) as data:
        return {name: data[name] for name in data.files}
