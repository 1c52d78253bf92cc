"""InterfaceData <-> numpy arrays without a Python float per value.

An InterfaceData is three packed `repeated double` fields (1 displacement,
2 velocity, 3 force): each a tag byte, a varint length, then the values as
little-endian binary64. Decoding its serialisation with np.frombuffer and
encoding arrays with tobytes() is several times cheaper than iterating the
repeated fields; anything unexpected falls back to the generic path.
"""

import struct

import numpy as np

NAMES = {1: "displacement", 2: "velocity", 3: "force"}
TAGS = {"displacement": 0x0A, "velocity": 0x12, "force": 0x1A}
F8 = np.dtype("<f8")
_REPORT = struct.Struct("<BdB")   # tag of t (field 2, 64-bit), t, tag of outputs (3, bytes)
_PEAK = struct.Struct("<BdB?")    # max_abs_displacement (4, 64-bit), finite (5, varint)


_VARINTS = {}  # the varints of the small numbers met so far (lengths, points, steps)


def _varint(n):
    b = _VARINTS.get(n)
    if b is not None:
        return b
    out = bytearray()
    m = n
    while m >= 0x80:
        out.append((m & 0x7F) | 0x80)
        m >>= 7
    out.append(m)
    if n < 0x4000:  # at most 16384 entries of one or two bytes
        _VARINTS[n] = bytes(out)
    return bytes(out)


_DOUBLES = {}  # struct.Struct per count of little-endian doubles


def _doubles(values):
    s = _DOUBLES.get(len(values))
    if s is None:
        s = _DOUBLES[len(values)] = struct.Struct("<%dd" % len(values))
    return s.pack(*values)


def field(number, payload):
    """A length-delimited field: its tag, the payload's length, the payload."""
    return bytes((number << 3 | 2,)) + _varint(len(payload)) + payload


def decode(idata):
    """{name: read-only float64 array} of the non-empty fields of an InterfaceData."""
    raw = idata.SerializeToString()
    out = {}
    pos, end = 0, len(raw)
    while pos < end:
        tag = raw[pos]
        pos += 1
        length = shift = 0
        while True:
            b = raw[pos]
            pos += 1
            length |= (b & 0x7F) << shift
            if b < 0x80:
                break
            shift += 7
        name = NAMES.get(tag >> 3)
        if name is None or tag & 7 != 2 or length % 8:  # not packed doubles: the slow way
            return {q: np.fromiter(getattr(idata, q), float, len(getattr(idata, q)))
                    for q in TAGS if len(getattr(idata, q))}
        out[name] = np.frombuffer(raw, F8, length // 8, pos)
        pos += length
    return out


def encode(values, sends):
    """The serialisation of an InterfaceData holding values[q] for q in sends."""
    parts = []
    for q in sends:
        b = np.ascontiguousarray(values[q], dtype=F8).tobytes()
        parts.append(bytes((TAGS[q],)) + _varint(len(b)) + b)
    return b"".join(parts)


def step_report(step, t, encoded, peak, finite, history):
    """The serialisation of a StepReport{step, t, outputs, max_abs_displacement,
    finite, history} whose outputs hold the given encoded InterfaceData, in
    order (every field written, its default too)."""
    outputs = b"".join([field(1, b) for b in encoded])
    return b"".join((b"\x08", _varint(step & 0xFFFFFFFFFFFFFFFF), _REPORT.pack(0x11, t, 0x1A),
                     _varint(len(outputs)), outputs, _PEAK.pack(0x21, peak, 0x28, bool(finite)),
                     b"\x32", _varint(8 * len(history)),
                     _doubles(history)))


def reports(req_id, chunks, waiting_for=""):
    """The serialisation of Envelope{id, reports: Reports{reports, waiting_for}}
    whose reports are the given serialised StepReports, in order."""
    body = b"".join([field(1, c) for c in chunks])
    if waiting_for:
        body += field(2, waiting_for.encode())
    return b"\x08" + _varint(req_id) + b"\x8a\x02" + _varint(len(body)) + body


def peer_data(point, encoded, last=False, refresh=False):
    """The serialisation of Envelope{peer_data: PeerData{point, data, last,
    refresh}} whose data holds the given encoded InterfaceData, in order."""
    data = b"".join(b"\x0a" + _varint(len(b)) + b for b in encoded)
    body = (b"\x08" + _varint(point) + b"\x12" + _varint(len(data)) + data
            + (b"\x18\x01" if last else b"") + (b"\x20\x01" if refresh else b""))
    return b"\x9a\x02" + _varint(len(body)) + body  # Envelope field 35, length-delimited


class Layout:
    """The one serialisation an InterfaceData has when it holds n values of
    each of `names` (and nothing else): the packed fields in field order,
    each a tag byte, the same varint length and 8 n bytes. Built once per
    session for each interface and direction, it reads such data as one
    (quantities x n) array without parsing, and writes it without a varint:
    a field order, count or quantity that differs is not that layout
    (view() returns None, and decode() takes over)."""

    __slots__ = ("names", "n", "size", "first", "stride", "headers")

    def __init__(self, names, n):
        self.names = tuple(sorted(names, key=TAGS.get))  # field order, as serialised
        self.n = n
        nbytes = 8 * n
        self.headers = [bytes((TAGS[q],)) + _varint(nbytes) for q in self.names]
        h = len(self.headers[0]) if self.headers else 0
        self.first, self.stride = h, h + nbytes
        self.size = self.stride * len(self.names)

    def view(self, raw):
        """The values of `raw` (an InterfaceData's serialisation) as a
        read-only (len(names), n) array, a view of raw's bytes; None when
        raw is not of this layout."""
        if len(raw) != self.size or not self.size:
            return None
        h, at = self.first, 0
        for head in self.headers:
            if raw[at:at + h] != head:
                return None
            at += self.stride
        return np.ndarray((len(self.names), self.n), F8, raw, h, (self.stride, 8))

    def encode(self, values):
        """The serialisation of values[q] for q in names (n values each,
        which the caller has checked)."""
        return b"".join([head + np.ascontiguousarray(values[q], dtype=F8).tobytes()
                         for head, q in zip(self.headers, self.names)])
