""".npz archives read member by member, a block at a time, and damaged ones named: a bad CRC, a
header that claims more than the member holds, a member that is no array."""

from __future__ import annotations

import io as _io
import tracemalloc
import warnings
import zipfile
from pathlib import Path

import numpy as np
import pytest

from gyrocore import io

N = 2_000_000  # 16 MB an array


@pytest.mark.parametrize("save", [np.savez, np.savez_compressed])
def test_an_npz_is_read_a_block_at_a_time(tmp_path: Path, save: object) -> None:
    t = np.arange(N) * 0.01
    rate = np.random.default_rng(0).normal(0.0, 0.01, N)
    path = tmp_path / "big.npz"
    save(path, t=t, gyro_z=rate)  # type: ignore[operator]
    src = io.open_source(path)
    next(iter(src.chunks(10)))  # the modules a first chunk imports (pyarrow's: 3 MB) are not the reading's
    tracemalloc.start()
    try:
        parts = [(c.t[[0, -1]], c.rate[[0, -1]]) for c in src.chunks(10_000)]
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 6e6  # np.load read each 16 MB member whole
    assert len(parts) == N // 10_000
    assert parts[-1][0][1] == t[-1] and parts[-1][1][1] == rate[-1]
    log = io.read_log(path)
    assert np.array_equal(log.t, t) and np.array_equal(log.rate, rate)


def _with_member(path: Path, members: dict[str, bytes]) -> Path:
    with zipfile.ZipFile(path, "w") as z:
        for name, data in members.items():
            z.writestr(name, data)
    return path


def _npy(array: np.ndarray) -> bytes:
    buf = _io.BytesIO()
    np.save(buf, array)
    return buf.getvalue()


def _claiming(shape: tuple[int, ...]) -> bytes:
    """An .npy member whose header claims ``shape`` of float64 and holds 80 bytes."""
    buf = _io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": "<f8", "fortran_order": False, "shape": shape})
    return buf.getvalue() + bytes(80)


def test_an_npz_member_claiming_a_terabyte_is_refused_before_it_is_read(tmp_path: Path) -> None:
    path = _with_member(tmp_path / "huge.npz", {"t.npy": _claiming((10**12,)), "gyro_z.npy": _claiming((10**12,))})
    with pytest.raises(ValueError) as info:
        io.read_log(path)
    assert str(info.value) == (f"{path}: member t ends early (truncated .npz): its header's shape (1000000000000,) "
                               "of float64 takes 8000000000000 bytes, it holds 80")


@pytest.mark.parametrize("compressed", [False, True])
def test_an_npz_with_a_damaged_member_is_named(tmp_path: Path, compressed: bool) -> None:
    path = tmp_path / "crc.npz"
    rate = np.random.default_rng(0).normal(0.0, 0.01, 1000)  # incompressible: the flipped byte is its data
    (np.savez_compressed if compressed else np.savez)(path, t=np.arange(1000) * 0.01, gyro_z=rate)
    data = bytearray(path.read_bytes())
    info = zipfile.ZipFile(path).getinfo("gyro_z.npy")
    name_and_extra = int.from_bytes(data[info.header_offset + 26:info.header_offset + 28], "little") + int.from_bytes(
        data[info.header_offset + 28:info.header_offset + 30], "little")
    data[info.header_offset + 30 + name_and_extra + info.compress_size - 100] ^= 0xFF  # the member's last values
    path.write_bytes(bytes(data))
    with pytest.raises(ValueError, match=rf"^{path}: damaged \.npz file \(member gyro_z: (BadZipFile|error): "):
        io.read_log(path)


def test_an_npz_member_with_a_broken_header_is_named_with_the_member(tmp_path: Path) -> None:
    path = _with_member(tmp_path / "cut.npz", {"t.npy": b"\x93NUMPY\x01\x00", "gyro_z.npy": _npy(np.zeros(3))})
    with pytest.raises(ValueError, match=rf"^{path}: member t: not a NumPy \.npy file \("):
        io.read_log(path)


def test_npz_members_named_without_npy_are_read_as_np_load_reads_them(tmp_path: Path) -> None:
    t, rate = np.arange(300) * 0.01, np.linspace(0, 0.1, 300).astype(">f4")
    path = _with_member(tmp_path / "bare.npz", {"t": _npy(t), "gyro_z": _npy(rate)})
    log = io.read_log(path)
    assert np.array_equal(log.t, t) and np.array_equal(log.rate, rate.astype(np.float64))


@pytest.mark.parametrize("second", ["gyro_z.npy", "gyro_z"])
def test_two_npz_members_of_one_name_are_refused_not_one_taken(tmp_path: Path, second: str) -> None:
    path = tmp_path / "twice.npz"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # zipfile's "Duplicate name": such archives exist all the same
        _with_member(path, {"t.npy": _npy(np.arange(3.0)), "gyro_z.npy": _npy(np.zeros(3))})
        with zipfile.ZipFile(path, "a") as z:
            z.writestr(second, _npy(np.ones(3)))
    with pytest.raises(ValueError) as info:
        io.read_log(path)
    assert str(info.value) == f"{path}: column(s) gyro_z appear more than once"
