"""Compiled tokenizer and exact float conversion for the numeric text tables (fast path).

np.loadtxt spends its time in the C library's string-to-double conversion (Python's dtoa,
about 0.5 µs a field, holding the GIL): a 1.8-million-line IMU file takes 3-4 s. Here one numba
loop over the file's bytes (read in blocks, so memory holds the values and two blocks) splits lines and
fields and converts each field with the Eisel-Lemire algorithm (Lemire, "Number parsing at a
gigabyte per second", 2021; as in the fast_float library): the 64-bit decimal significand times a
128-bit approximation of 5**q gives the correctly rounded double, and the rare cases the
approximation cannot decide are reported, not guessed.

The fast path only accepts what it is sure of and gives exactly np.loadtxt's values there:

* fields ``[+-]digits[.digits][e[+-]digits]`` (at most 19 significant digits, a normal double),
* separated by spaces/tabs, or by commas with spaces/tabs around them,
* ``#``/``%`` comments, blank lines, LF or CRLF line ends, the same field count on every line.

Anything else (a wrong field count, a word, ``nan``, an empty comma field, a lone CR, a
subnormal, a halfway case Eisel-Lemire cannot decide) makes :func:`parse_numeric_file` return
None and the caller runs the general parser, which gives the values or the error naming the line.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from insrail.jit import cached_njit

_SMALLEST_POWER_OF_FIVE = -342
_LARGEST_POWER_OF_FIVE = 308
_MAX_SIGNIFICANT_DIGITS = 19


def _powers_of_five_128() -> np.ndarray:
    """(hi, lo) 64-bit words of the 128-bit normalised 5**q, q in [-342, 308]: truncated for
    q >= 0, the reciprocal rounded up for q < 0 (the table fast_float generates)."""
    table = []
    for q in range(_SMALLEST_POWER_OF_FIVE, 0):
        power5 = 5 ** -q
        z = power5.bit_length() if power5 & (power5 - 1) else power5.bit_length() - 1
        bits = z + 127 if q >= -27 else 2 * z + 128
        c = (1 << bits) // power5 + 1
        table.append(c >> max(c.bit_length() - 128, 0))  # its top 128 bits
    for q in range(0, _LARGEST_POWER_OF_FIVE + 1):
        power5 = 5 ** q
        shift = 128 - power5.bit_length()  # normalised: the highest of 128 bits set
        table.append(power5 << shift if shift >= 0 else power5 >> -shift)
    mask = (1 << 64) - 1
    return np.array([[c >> 64, c & mask] for c in table], dtype=np.uint64)


_POWERS_OF_FIVE = _powers_of_five_128()

_U32 = np.uint64(0xFFFFFFFF)
_ALL_ONES = np.uint64(0xFFFFFFFFFFFFFFFF)
_PRECISION_MASK = np.uint64(0x1FF)  # the 64 - (52 + 3) low bits of the high word
_HIDDEN_BIT = np.uint64(1 << 52)
_U0, _U1, _U2, _U3 = np.uint64(0), np.uint64(1), np.uint64(2), np.uint64(3)
_S32 = np.uint64(32)

compiled = cached_njit(nogil=True)


@compiled
def _multiply_64x64(a, b):
    """(high, low) words of the 128-bit product of two uint64."""
    a_lo, a_hi = a & _U32, a >> _S32
    b_lo, b_hi = b & _U32, b >> _S32
    lo_lo = a_lo * b_lo
    hi_lo = a_hi * b_lo
    lo_hi = a_lo * b_hi
    hi_hi = a_hi * b_hi
    cross = (lo_lo >> _S32) + (hi_lo & _U32) + lo_hi
    high = hi_hi + (hi_lo >> _S32) + (cross >> _S32)
    low = (cross << _S32) | (lo_lo & _U32)
    return high, low


@compiled
def _double_bits(w, q, negative, powers):
    """IEEE bits of the double nearest to w * 10**q (w > 0), or -1 when Eisel-Lemire cannot
    decide or the result is not a normal finite double."""
    if q < _SMALLEST_POWER_OF_FIVE or q > _LARGEST_POWER_OF_FIVE:
        return -1
    lz = 0
    while w < np.uint64(1 << 63):
        w = w << _U1
        lz += 1
    index = q - _SMALLEST_POWER_OF_FIVE
    high, low = _multiply_64x64(w, powers[index, 0])
    if (high & _PRECISION_MASK) == _PRECISION_MASK:
        second_high, _ = _multiply_64x64(w, powers[index, 1])
        low = low + second_high
        if second_high > low:
            high = high + _U1
    if low == _ALL_ONES and not (-27 <= q <= 55):
        return -1  # needs more precision than 128 bits: the general parser decides
    upperbit = np.int64(high >> np.uint64(63))
    mantissa = high >> np.uint64(upperbit + 9)
    power2 = (((152170 + 65536) * q) >> 16) + 63 + upperbit - lz + 1023
    if power2 <= 0:
        return -1  # subnormal or zero
    if low <= _U1 and -4 <= q <= 23 and (mantissa & _U3) == _U1:
        if (mantissa << np.uint64(upperbit + 9)) == high:
            mantissa = mantissa & ~_U1  # exactly halfway: round to even, not up
    mantissa = mantissa + (mantissa & _U1)
    mantissa = mantissa >> _U1
    if mantissa >= (_U2 << np.uint64(52)):
        mantissa = _HIDDEN_BIT
        power2 += 1
    mantissa = mantissa & ~_HIDDEN_BIT
    if power2 >= 0x7FF:
        return -1
    bits = mantissa | (np.uint64(power2) << np.uint64(52))
    if negative:
        bits = bits | np.uint64(1 << 63)
    return np.int64(bits)


@compiled
def _is_blank(byte):
    return byte == 32 or byte == 9


@compiled
def _is_comment(byte):
    return byte == 35 or byte == 37  # '#', '%'


@compiled
def _skip_lines(data, count):
    """(offset after up to ``count`` lines, lines still to skip), or (-1, 0) on a lone carriage
    return (the general parser's universal newlines would count lines differently)."""
    position, n = 0, len(data)
    while count > 0 and position < n:
        byte = data[position]
        if byte == 13 and (position + 1 >= n or data[position + 1] != 10):
            return -1, 0
        if byte == 10:
            count -= 1
        position += 1
    return position, count


@compiled
def _parse_number(data, position, negative):
    """(position after the number, IEEE bits) of the number at ``position`` (sign consumed), or
    (-1, 0) when it is not a plain decimal number the fast path converts exactly."""
    n = len(data)
    w = np.uint64(0)
    significant = 0
    digits = 0
    exponent = 0
    fraction = False
    while position < n:
        byte = data[position]
        if 48 <= byte <= 57:
            digit = byte - 48
            if significant > 0 or digit != 0:
                significant += 1
                if significant > _MAX_SIGNIFICANT_DIGITS:
                    return -1, 0
                w = w * np.uint64(10) + np.uint64(digit)
            if fraction:
                exponent -= 1
            digits += 1
        elif byte == 46 and not fraction:
            fraction = True
        else:
            break
        position += 1
    if digits == 0:
        return -1, 0
    if position < n and (data[position] == 101 or data[position] == 69):  # e, E
        position += 1
        exponent_negative = False
        if position < n and (data[position] == 43 or data[position] == 45):
            exponent_negative = data[position] == 45
            position += 1
        exponent_digits = 0
        explicit = 0
        while position < n and 48 <= data[position] <= 57:
            explicit = explicit * 10 + (data[position] - 48)
            exponent_digits += 1
            position += 1
        if exponent_digits == 0 or exponent_digits > 4:
            return -1, 0
        exponent += -explicit if exponent_negative else explicit
    if w == 0:
        return position, (np.int64(-0x8000000000000000) if negative else np.int64(0))
    bits = _double_bits(w, exponent, negative, _POWERS_OF_FIVE)
    if bits == -1:
        return -1, 0
    return position, bits


@compiled
def _parse(data, start, comma, out_bits, rows, columns):
    """Fill out_bits from row ``rows`` on with the IEEE bits of the fields of data's lines from
    byte ``start`` on, one row a data line, up to out_bits.shape[0] rows; ``columns`` is the
    field count of the rows before (-1: none yet). Returns (rows, columns) after these lines, or
    (-1, 0) when the file needs the general parser."""
    n = len(data)
    max_rows, max_columns = out_bits.shape
    position = start
    while position < n and rows < max_rows:
        field = 0
        blank_only = False
        after_comma = False
        while True:  # the fields of one line
            while position < n and _is_blank(data[position]):
                position += 1
                blank_only = field == 0
            if position >= n:
                break
            byte = data[position]
            if byte == 10 or _is_comment(byte):
                break
            if byte == 13:
                if position + 1 < n and data[position + 1] == 10:
                    break
                return -1, 0  # a lone carriage return
            if comma and field > 0 and not after_comma:
                return -1, 0
            negative = byte == 45
            if byte == 43 or byte == 45:
                position += 1
            position, bits = _parse_number(data, position, negative)
            if position < 0 or field >= max_columns:
                return -1, 0
            if position < n:
                end = data[position]
                if not (_is_blank(end) or end == 10 or end == 13 or _is_comment(end) or (comma and end == 44)):
                    return -1, 0  # a field that is not only a number
            out_bits[rows, field] = bits
            field += 1
            after_comma = False
            while position < n and _is_blank(data[position]):
                position += 1
            if comma and position < n and data[position] == 44:
                position += 1
                after_comma = True
        if after_comma:
            return -1, 0  # an empty field after a comma
        while position < n and data[position] != 10:  # the comment and the line end
            if data[position] == 13 and (position + 1 >= n or data[position + 1] != 10):
                return -1, 0
            position += 1
        position += 1
        if field == 0:
            if comma and blank_only:
                return -1, 0  # a comma table's blank-only line: left to the general parser
            continue
        if columns == -1:
            columns = field
        elif field != columns:
            return -1, 0
        rows += 1
    return rows, columns


#: fields a line can hold within the line length limit (a number and a separator each)
_PROBE_COLUMNS = 1 << 15
#: bytes read at a time: memory stays the values plus two blocks, whatever the file's size
_BLOCK_BYTES = 1 << 24


def _blocks_of_whole_lines(handle):
    """The file's bytes in blocks of about :data:`_BLOCK_BYTES` that end at a line end (the last
    one at the end of the file); check_text_file bounds a line, so every block holds one. Each block
    is a view of one buffer the file is read into (no copy of it made), good until the next block
    is asked for; the part of a line after a block's last line end moves to the buffer's front."""
    # a file smaller than a block is read in one block of its size: a 32 MB buffer zeroed for a small file
    # was most of its read
    block_bytes = max(min(_BLOCK_BYTES, os.fstat(handle.fileno()).st_size + 1), 1)
    buffer = bytearray(2 * block_bytes)
    carried = 0  # bytes of the next block already in the buffer's front
    while True:
        if len(buffer) - carried < block_bytes:  # a line longer than a block (not after check_text_file)
            grown = bytearray(2 * len(buffer))
            grown[:carried] = buffer[:carried]
            buffer = grown
        got = handle.readinto(memoryview(buffer)[carried:carried + block_bytes])
        if not got:
            if carried:
                yield memoryview(buffer)[:carried]
            return
        filled = carried + got
        cut = buffer.rfind(b"\n", 0, filled) + 1
        if cut:
            yield memoryview(buffer)[:cut]
        buffer[:filled - cut] = buffer[cut:filled]
        carried = filled - cut


@compiled
def line_scan(data, run, max_line_chars):
    """One block of a text file's bytes after ``run`` bytes of a line begun before it: (the line
    ends in the block, the index among them of the first line longer than ``max_line_chars`` or -1
    (the scan stops there), the bytes of the line still open after the block).
    :func:`insrail.io.textparse.check_text_file`'s count, in one pass without temporary arrays."""
    ended = 0
    for i in range(data.shape[0]):
        if data[i] == 10:
            if run > max_line_chars:
                return ended, ended, run
            ended += 1
            run = 0
        else:
            run += 1
    return ended, -1, run


def parse_numeric_file(path: Path, skip_lines: int, comma: bool, line_count: int) -> np.ndarray | None:
    """(rows, columns) float64 of the file's data lines after ``skip_lines`` lines, exactly as
    np.loadtxt reads them, or None when the file needs the general parser (see the module
    docstring). ``line_count`` bounds the rows (from :func:`insrail.io.textparse.check_text_file`)."""
    out_bits = None
    rows, columns = 0, -1
    with open(path, "rb") as handle:
        for block in _blocks_of_whole_lines(handle):
            data = np.frombuffer(block, dtype=np.uint8)
            start = 0
            if skip_lines:
                start, skip_lines = _skip_lines(data, skip_lines)
                if start < 0:
                    return None
            if out_bits is None:  # the first data row's field count sizes the values
                probe = np.empty((1, _PROBE_COLUMNS), dtype=np.int64)
                found, columns = _parse(data, start, comma, probe, 0, -1)
                if found < 0:
                    return None
                if found == 0:
                    continue  # no data row in this block
                out_bits = np.empty((max(line_count, 1), columns), dtype=np.int64)
            rows, columns = _parse_halves(data, start, comma, out_bits, rows, columns)
            if rows < 0:
                return None
    if out_bits is None:
        return None
    return out_bits[:rows].view(np.float64)


#: a block's bytes from which its two halves are parsed side by side (:func:`_parse_halves`)
_SPLIT_BYTES = 1 << 20
#: bytes after a block's middle searched for the line end its second half starts after (check_text_file bounds a line)
_SPLIT_SEARCH = 1 << 17


def _parse_halves(data, start, comma, out_bits, rows, columns) -> tuple[int, int]:
    """:func:`_parse` of a block of whole lines from byte ``start`` on (the field count ``columns`` known):
    its second half (from a line end after its middle) in a background job beside the first (the kernel
    runs without the GIL), into values of its own that are then put after the first half's rows. In one
    piece with one CPU or for a small block. The same result as one call over the block."""
    from insrail.background import BackgroundJob, cpu_budget

    middle = start + (len(data) - start) // 2
    ends = np.flatnonzero(data[middle : middle + _SPLIT_SEARCH] == 10)
    if len(data) - start < _SPLIT_BYTES or not len(ends) or cpu_budget() < 2:
        return _parse(data, start, comma, out_bits, rows, columns)
    first, second = data[: middle + int(ends[0]) + 1], data[middle + int(ends[0]) + 1 :]

    def parse_second(progress, cancel):
        values = np.empty((int(np.count_nonzero(second == 10)) + 1, out_bits.shape[1]), dtype=np.int64)
        return values, _parse(second, 0, comma, values, 0, columns)[0]

    with BackgroundJob(parse_second, None, None, name="insrail-parsing") as job:
        rows, columns = _parse(first, start, comma, out_bits, rows, columns)
        values, more = job.result()
    if rows < 0 or more < 0:
        return -1, 0
    out_bits[rows : rows + more] = values[:more]
    return rows + more, columns
