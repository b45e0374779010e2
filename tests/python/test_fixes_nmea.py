"""NMEA files that are damaged, empty or of no use: gyrocore.fixes.read_nmea names the file and
line of what it cannot use, and says when a file gives no fix."""

from __future__ import annotations

from pathlib import Path

import pytest

from gyrocore import InputWarning
from gyrocore.fixes import read_nmea

pynmea2 = pytest.importorskip("pynmea2")


def rmc(time: str = "123519", *, status: str = "A", speed: str = "010.0", course: str = "084.4",
        date: str = "230394", variation: tuple[str, str] = ("003.1", "W"), mode: tuple[str, ...] = ()) -> str:
    """An RMC sentence with a valid checksum over whatever its fields hold (``variation``: its
    magnetic variation, degrees and E or W; ``mode``: its mode indicator, NMEA 2.3 on)."""
    return str(pynmea2.RMC("GP", "RMC", (time, status, "4807.038", "N", "01131.000", "E", speed, course, date,
                                         *variation, *mode)))


def nmea(tmp_path: Path, *lines: str) -> Path:
    path = tmp_path / "drive.nmea"
    path.write_text("".join(f"{line}\n" for line in lines))
    return path


@pytest.mark.parametrize("field", [{"course": "abc"}, {"speed": "x"}, {"date": "320394"}, {"time": "996519"}])
def test_a_field_that_is_not_a_value_names_its_line(tmp_path: Path, field: dict[str, str]) -> None:
    # pynmea2 hands such a field back as its text: float() of it, or a date made of it, failed
    # without naming the file (a ValueError, or a TypeError from datetime.combine)
    path = nmea(tmp_path, rmc("123518"), rmc(**field))
    with pytest.raises(ValueError, match=r"drive.nmea: line 2: an RMC sentence whose .* cannot be read"):
        read_nmea(path)


@pytest.mark.parametrize("speed", ["-5.0", "nan"])
def test_a_speed_that_is_no_speed_names_its_line(tmp_path: Path, speed: str) -> None:
    # the error named speed[1], the epoch's place among the epochs, not the line
    path = nmea(tmp_path, "$GPGSV,3,1,11,03,03,111,00,04,15,270,00,06,01,010,00,13,06,292,00*74", rmc("123518"),
                rmc("123519", speed=speed))
    with pytest.raises(ValueError, match=r"drive.nmea: line 3: speed\[1\] is "):
        read_nmea(path)


def test_a_file_without_a_sentence_is_an_error(tmp_path: Path) -> None:
    # it gave no fix without a word, where an empty fixes.csv or gnss.csv is refused
    with pytest.raises(ValueError, match=r"drive.nmea: no NMEA sentence"):
        read_nmea(nmea(tmp_path, "", "  "))


def test_sentences_of_no_fix_warn_with_their_counts(tmp_path: Path) -> None:
    gga = "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47"
    path = nmea(tmp_path, rmc("123519", status="V"), rmc("123520", status="V"), gga, rmc("123521", course=""))
    with pytest.warns(InputWarning, match=r"no heading fix from .*drive.nmea: of its 4 sentences, 3 are RMC: 2 void "
                                          r"\(status V\), 1 without a course"):
        assert len(read_nmea(path)) == 0


def test_a_log_of_positions_alone_says_what_to_do(tmp_path: Path) -> None:
    # a GGA or GNS log said "none is RMC" and no more
    gga = "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47"
    gns = str(pynmea2.GNS("GN", "GNS", ("123520", "4807.038", "N", "01131.000", "E", "AN", "08", "0.9", "545.4",
                                       "46.9", "", "")))
    with pytest.warns(InputWarning, match=r"of its 2 sentences, none is RMC; 2 are GGA, GNS or GLL, positions without "
                                          r"a course: set the receiver to write RMC \(and VTG\), or take the course "
                                          r"of each step between positions with gyrocore.fixes.from_latlon"):
        assert len(read_nmea(nmea(tmp_path, gga, gns))) == 0


def test_a_checksum_in_lower_case_hex_and_crlf_line_ends_are_read(tmp_path: Path) -> None:
    # receivers and loggers write either case, and serial logs end lines with CR LF
    lines = [rmc(f"1235{s:02d}") for s in range(20)]
    assert any(c in "ABCDEF" for line in lines for c in line[-2:])
    path = tmp_path / "drive.nmea"
    path.write_bytes("".join(f"{line[:-2]}{line[-2:].lower()}\r\n" for line in lines).encode())
    assert len(read_nmea(path)) == 20


def test_a_sentence_of_a_type_pynmea2_does_not_know_is_skipped(tmp_path: Path) -> None:
    # "Other sentences are skipped", but one of a type pynmea2 lacks was "not an NMEA sentence"
    unknown = "$GPXYZ,1,2,3*50"
    assert len(read_nmea(nmea(tmp_path, unknown, rmc()))) == 1
    with pytest.raises(ValueError, match="line 1: not an NMEA sentence .*checksum does not match"):
        read_nmea(nmea(tmp_path, unknown.replace("*50", "*51"), rmc()))


def test_a_byte_order_mark_is_not_part_of_the_first_sentence(tmp_path: Path) -> None:
    path = tmp_path / "drive.nmea"
    path.write_text(f"{rmc('123519')}\r\n{rmc('123520')}\r\n", encoding="utf-8-sig")
    assert len(read_nmea(path)) == 2


def test_a_line_longer_than_any_sentence_is_refused_unread(tmp_path: Path) -> None:
    path = tmp_path / "drive.nmea"
    path.write_text(rmc() + "\n$" + "A" * 5_000_000)
    with pytest.raises(ValueError, match=r"drive.nmea: line 2: longer than 4096 characters"):
        read_nmea(path)
