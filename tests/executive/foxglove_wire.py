"""Reading Foxglove's protobuf messages back without the protobuf package: the wire
format's varints, doubles and length-delimited fields, enough for the tests to check
values in a recording (field numbers from Foxglove's .proto files, checked against the
schema's descriptor in the tests)."""

from __future__ import annotations

import struct


def fields(data: bytes) -> dict[int, list[object]]:
    """Each field number's values: ints (varint, fixed32), floats (64-bit), bytes (length-delimited)."""
    out: dict[int, list[object]] = {}
    i = 0
    while i < len(data):
        key, i = _varint(data, i)
        number, wire = key >> 3, key & 7
        value: object
        if wire == 0:
            value, i = _varint(data, i)
        elif wire == 1:
            value, i = struct.unpack_from("<d", data, i)[0], i + 8
        elif wire == 2:
            size, i = _varint(data, i)
            value, i = data[i:i + size], i + size
        elif wire == 5:
            value, i = struct.unpack_from("<I", data, i)[0], i + 4  # fixed32: sizes, steps
        else:
            raise ValueError(f"wire type {wire} not expected in a Foxglove message")
        out.setdefault(number, []).append(value)
    return out


def doubles(packed: bytes) -> list[float]:
    """A packed ``repeated double``."""
    return list(struct.unpack(f"<{len(packed) // 8}d", packed))


def vector(data: bytes) -> tuple[float, float, float]:
    """A foxglove.Vector3 (x=1, y=2, z=3; an omitted field is 0)."""
    f = fields(data)
    return tuple(float(f.get(n, [0.0])[0]) for n in (1, 2, 3))  # type: ignore[return-value]


def _varint(data: bytes, i: int) -> tuple[int, int]:
    shift = value = 0
    while True:
        byte = data[i]
        i += 1
        value |= (byte & 0x7F) << shift
        if not byte & 0x80:
            return value, i
        shift += 7


def numbers(schema: bytes, message: str) -> dict[str, int]:
    """Field name to number for ``foxglove.<message>``, read from a channel's schema (a
    protobuf FileDescriptorSet: file=1; FileDescriptorProto name=1, package=2,
    message_type=4; DescriptorProto name=1, field=2; FieldDescriptorProto name=1, number=3)."""
    for file in fields(schema)[1]:
        for described in fields(file).get(4, []):  # type: ignore[arg-type]
            d = fields(described)  # type: ignore[arg-type]
            if d[1][0] == message.encode():
                return {fields(f)[1][0].decode(): fields(f)[3][0] for f in d.get(2, [])}  # type: ignore
    raise KeyError(f"{message} is not described in the schema")


def named(data: bytes, schema: bytes, message: str) -> dict[str, list[object]]:
    """A message's fields by name, per its schema."""
    by_number = {n: name for name, n in numbers(schema, message).items()}
    return {by_number[n]: values for n, values in fields(data).items()}
