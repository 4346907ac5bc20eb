"""The compiled text reader gives np.loadtxt's values bit for bit, hands everything it is not sure
of to the general parser, and read_numeric_table's errors stay the same (file, line, what was
expected) for every kind of malformed input."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from insrail import background
from insrail.io import fastparse
from insrail.io.errors import InputError
from insrail.io.fastparse import parse_numeric_file
from insrail.io.textparse import MAX_LINE_CHARS, check_text_file, read_numeric_table

FORMATS = ("%r", "%.16e", "%.17g", "%.9f", "%.6f", "%g", "%.3E")
normal_floats = st.floats(allow_nan=False, allow_infinity=False, allow_subnormal=False,
                          min_value=-1e300, max_value=1e300)


def bits(values: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(values, dtype=np.float64).view(np.int64)


def fast(path, skip_lines=0, comma=False):
    return parse_numeric_file(path, skip_lines, comma, check_text_file(path))


def written(tmp_path, text: str, name="table.txt"):
    path = tmp_path / name
    path.write_bytes(text.encode("latin-1"))
    return path


#: A block for the generated examples' small files: each file one block, as with the reader's own 16 MB block
#: (whose 32 MB buffer, zeroed per file read, was most of an example's time); the block boundaries have their
#: own test (test_an_imu_file_as_insrail_writes_it_takes_the_fast_path)
SMALL_FILE_BLOCK_BYTES = 1 << 16


def one_block(path):
    assert path.stat().st_size < SMALL_FILE_BLOCK_BYTES
    return path


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(rows=st.lists(st.lists(normal_floats, min_size=3, max_size=3), min_size=1, max_size=12),
       fmt=st.sampled_from(FORMATS), separator=st.sampled_from([" ", "\t", "  ", ",", " , "]),
       line_end=st.sampled_from(["\n", "\r\n"]), comment=st.sampled_from(["", " # note", "% x,y"]),
       blank_lines=st.booleans())
def test_values_are_np_loadtxt_values_bit_for_bit(tmp_path, monkeypatch, rows, fmt, separator, line_end, comment,
                                                  blank_lines):
    monkeypatch.setattr(fastparse, "_BLOCK_BYTES", SMALL_FILE_BLOCK_BYTES)
    lines = ["# t x y", *(separator.join(fmt % v for v in row) + comment for row in rows)]
    if blank_lines:
        lines.insert(2, "")
    path = one_block(written(tmp_path, line_end.join(lines) + line_end))
    comma = "," in separator
    expected = np.loadtxt(path, comments=("#", "%"), delimiter="," if comma else None, ndmin=2)
    parsed = fast(path, comma=comma)
    if parsed is not None:  # None only for a number Eisel-Lemire leaves undecided
        assert np.array_equal(bits(parsed), bits(expected))
    assert np.array_equal(bits(read_numeric_table(path).values), bits(expected))


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(significand=st.integers(1, 10**19 - 1), exponent=st.integers(-330, 290), point=st.integers(0, 19),
       negative=st.booleans())
def test_every_decimal_converts_as_python_does(tmp_path, monkeypatch, significand, exponent, point, negative):
    """Hard cases: up to 19 significant digits, any exponent of a normal double, halfway points."""
    monkeypatch.setattr(fastparse, "_BLOCK_BYTES", SMALL_FILE_BLOCK_BYTES)
    digits = str(significand)
    point = min(point, len(digits))
    token = ("-" if negative else "") + digits[:len(digits) - point] + "." + digits[len(digits) - point:] \
        + f"e{exponent}"
    value = float(token)
    path = one_block(written(tmp_path, f"1.0 {token}\n"))
    parsed = fast(path)
    if parsed is None:  # subnormal, overflow or undecided: the general parser reads it
        parsed = read_numeric_table(path).values if np.isfinite(value) else np.array([[1.0, value]])
    assert bits(parsed[0, 1:]) == bits(np.array([value]))


@pytest.mark.parametrize("token", ["9007199254740993", "9007199254740995", "0.1", "1e23", "-0.0", "+5",
                                   "2.2250738585072014e-308", "1.7976931348623157e308",
                                   "7.3177701707893310e+15", "4.35e-6", ".5", "5.", "0000012.500"])
def test_known_hard_numbers_take_the_fast_path_exactly(tmp_path, token):
    path = written(tmp_path, f"{token} 1\n")
    parsed = fast(path)
    assert parsed is not None
    assert bits(parsed[0, :1]) == bits(np.array([float(token)]))


@pytest.mark.parametrize("block_bytes", [None, 100, 4096])
def test_an_imu_file_as_insrail_writes_it_takes_the_fast_path(tmp_path, monkeypatch, block_bytes):
    """Whole lines a block, whatever the block size (the header lines too may span blocks)."""
    if block_bytes:
        monkeypatch.setattr(fastparse, "_BLOCK_BYTES", block_bytes)
    rng = np.random.default_rng(3)
    data = np.column_stack([456300 + np.arange(1, 2001) / 200, rng.normal(0, 1e-4, (2000, 6))])
    path = tmp_path / "imu.txt"
    with open(path, "w") as handle:
        handle.write("# format: kfgins-imu\n# gps_week = 2380\n# " + "columns " * 20 + "\n")
        np.savetxt(handle, data, fmt=["%.9f"] + ["%.16e"] * 6)
    parsed = fast(path, skip_lines=3)
    assert parsed is not None and np.array_equal(bits(parsed), bits(np.loadtxt(path, ndmin=2)))


@pytest.mark.parametrize("bad_row", [None, 40, 1990])
def test_the_halves_of_a_block_parsed_side_by_side_give_the_values_of_one_pass(tmp_path, monkeypatch, bad_row):
    """Each block's second half (from a line end after its middle) parsed in a thread beside the first: the
    values are those of one pass, and a row with a field too few in either half still hands the file to
    the general parser."""
    monkeypatch.setattr(background, "cpu_budget", lambda: 2)  # also with one CPU
    monkeypatch.setattr(fastparse, "_BLOCK_BYTES", 4096)
    monkeypatch.setattr(fastparse, "_SPLIT_BYTES", 64)
    rng = np.random.default_rng(4)
    data = np.column_stack([456300 + np.arange(1, 2001) / 200, rng.normal(0, 1e-4, (2000, 6))])
    path = tmp_path / "imu.txt"
    np.savetxt(path, data, fmt=["%.9f"] + ["%.16e"] * 6, header="format: kfgins-imu")
    if bad_row is not None:
        lines = path.read_text().splitlines(keepends=True)
        lines[1 + bad_row] = lines[1 + bad_row].rsplit(" ", 1)[0] + "\n"
        path.write_text("".join(lines))
    parsed = fast(path, skip_lines=1)
    if bad_row is None:
        assert parsed is not None and np.array_equal(bits(parsed), bits(np.loadtxt(path, ndmin=2)))
    else:
        assert parsed is None


MALFORMED = [  # (file content, the error's line, what the message says)
    ("1 2 3\n4 5\n", 2, "expected 3 columns, found 2"),
    ("1 2 3\n4 5 6 7\n", 2, "expected 3 columns, found 4"),
    ("1 2 3\n4 x 6\n", 2, "column 2: expected a number, found 'x'"),
    ("1 2 3\n4 5 1,5\n", 2, "column 3: expected a number, found '1,5'"),
    ("1,2,3\n4,,6\n", 2, "column 2 is empty"),
    ("1 2 3\n4 5 6e\n", 2, "column 3: expected a number, found '6e'"),
    ("1 2 3\n4 5 --6\n", 2, "column 3: expected a number, found '--6'"),
    ("1 2 3\n4 5 nan\n", 2, "column 3 is nan: expected a finite number"),
    ("1 2 3\n4 5 1e999\n", 2, "column 3 is inf: expected a finite number"),
]


@pytest.mark.parametrize("content, line, message", MALFORMED)
def test_malformed_lines_give_the_general_parsers_error(tmp_path, content, line, message):
    path = written(tmp_path, content)
    assert fast(path, comma="," in content.splitlines()[0]) is None or "finite" in message
    with pytest.raises(InputError) as caught:
        read_numeric_table(path)
    assert str(path) in str(caught.value) and f"line {line}" in str(caught.value)
    assert message in str(caught.value)


def test_a_nul_byte_is_refused_as_binary(tmp_path):
    path = tmp_path / "table.txt"
    path.write_bytes(b"1 2 3\n4 5\x006\n")
    with pytest.raises(InputError, match="line 2.*binary data"):
        read_numeric_table(path)


def test_an_overlong_line_is_refused(tmp_path):
    path = written(tmp_path, "1 2 3\n" + "1 " * (MAX_LINE_CHARS // 2 + 1) + "\n")
    with pytest.raises(InputError, match="line 2.*longer than the limit"):
        read_numeric_table(path)


def test_too_many_lines_are_refused(tmp_path):
    path = written(tmp_path, "1 2 3\n" * 31)
    with pytest.raises(InputError, match="line 31.*more than the limit of 30 lines"):
        check_text_file(path, max_lines=30)
    assert check_text_file(path, max_lines=31) == 31


def test_a_small_file_is_read_into_a_buffer_of_its_size_not_a_whole_block(tmp_path):
    path = written(tmp_path, "1 2 3\n4 5 6\n")
    with open(path, "rb") as handle:
        blocks = [bytes(block) for block in fastparse._blocks_of_whole_lines(handle)]
        handle.seek(0)
        first = next(fastparse._blocks_of_whole_lines(handle))
        assert len(first.obj) <= 2 * (path.stat().st_size + 1)
    assert blocks == [b"1 2 3\n4 5 6\n"]


def test_the_powers_of_five_are_fast_floats_table():
    """The table of 128-bit powers of five (normalised with bit lengths at import) is the one normalising
    them a bit at a time gives, as fast_float generates it."""
    expected = []
    for q in range(fastparse._SMALLEST_POWER_OF_FIVE, 0):
        power5 = 5 ** -q
        z = power5.bit_length() if power5 & (power5 - 1) else power5.bit_length() - 1
        c = (1 << (z + 127 if q >= -27 else 2 * z + 128)) // power5 + 1
        while c >= 1 << 128:
            c >>= 1
        expected.append(c)
    for q in range(0, fastparse._LARGEST_POWER_OF_FIVE + 1):
        power5 = 5 ** q
        while power5 < 1 << 127:
            power5 <<= 1
        while power5 >= 1 << 128:
            power5 >>= 1
        expected.append(power5)
    table = fastparse._POWERS_OF_FIVE
    assert [(int(hi) << 64) | int(lo) for hi, lo in table] == expected
    assert (int(table[-fastparse._SMALLEST_POWER_OF_FIVE][0]), int(table[-fastparse._SMALLEST_POWER_OF_FIVE][1])) == (1 << 63, 0)
