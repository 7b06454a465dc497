#!/usr/bin/env python3
"""Rewrites a PC (Intel, processor byte 84) C3D file as an SGI (MIPS, byte 86) one: every 16-bit
integer and 32-bit float of the header, the parameter section and the data section byte-swapped,
nothing else changed. Independent of synsculpt's reader: it walks the file with the C3D
specification (c3d.org, "The C3D File Format User Guide"), reading Intel numbers with `struct`.

    python3 c3d_to_mips.py IN_intel.c3d OUT_mips.c3d

Used by tests/ingest/c3d_processor_test.cpp (C3dProcessors.MipsCopiesOfEveryIntelFileReadIdentically): the
MIPS copy must read exactly as the original. Exits 3 for a damaged parameter section whose records overlap
(no faithful copy exists).
"""
import array
import struct
import sys


def swap16(buffer, at):
    buffer[at], buffer[at + 1] = buffer[at + 1], buffer[at]


def swap32(buffer, at):
    buffer[at:at + 4] = buffer[at:at + 4][::-1]


def main(source, destination):
    data = bytearray(open(source, 'rb').read())
    original = bytes(data)
    parameter_block = original[0]
    parameter_start = (parameter_block - 1) * 512
    if original[parameter_start + 3] != 84:
        sys.exit(f'{source}: processor byte {original[parameter_start + 3]} is not 84 (Intel)')

    # Header: words (1-based) 2-6, 9, 10 and 148-151 are int16; words 7-8 (scale), 11-12 (rate) and
    # the 18 event times at words 153-188 are floats. Word 1 is two single bytes.
    for word in (2, 3, 4, 5, 6, 9, 10, 148, 149, 150, 151):
        swap16(data, 2 * (word - 1))
    for byte in (12, 20):
        swap32(data, byte)
    for event in range(18):
        swap32(data, 304 + 4 * event)
    (scale,) = struct.unpack_from('<f', original, 12)
    (data_block,) = struct.unpack_from('<H', original, 16)

    # Parameter section: 4-byte header (processor byte becomes 86), then records.
    data[parameter_start + 3] = 86
    position = parameter_start + 4
    while position + 2 <= len(original):
        name_length = abs(struct.unpack_from('<b', original, position)[0])
        group = struct.unpack_from('<b', original, position + 1)[0]
        if name_length == 0 or group == 0:
            break
        offset_at = position + 2 + name_length
        (next_offset,) = struct.unpack_from('<h', original, offset_at)
        swap16(data, offset_at)
        body_end = offset_at + 2  # where this record's numbers end, to detect records that overlap
        if group > 0:  # a parameter: type, dimensions, data
            type_at = offset_at + 2
            (value_type,) = struct.unpack_from('<b', original, type_at)
            dimension_count = original[type_at + 1]
            dimensions = original[type_at + 2:type_at + 2 + dimension_count]
            count = 1
            for dimension in dimensions:
                count *= dimension
            values_at = type_at + 2 + dimension_count
            if value_type == 2:
                for k in range(count):
                    swap16(data, values_at + 2 * k)
            elif value_type == 4:
                for k in range(count):
                    swap32(data, values_at + 4 * k)
            body_end = values_at + count * abs(value_type)  # (a description may follow, or not: OptiTrack)
        if next_offset == 0:
            break
        if offset_at + next_offset < body_end:
            # A damaged section: the next record starts inside this one, so one byte would be both a number to
            # swap and a character to keep. Such a file has no faithful MIPS copy.
            print(f'{source}: parameter record at byte {position} overlaps the next (damaged section)', file=sys.stderr)
            sys.exit(3)
        position = offset_at + next_offset

    # Data section: every value has the storage's width (points and analog alike).
    width = 4 if scale < 0 else 2
    start = (data_block - 1) * 512
    end = start + (len(data) - start) // width * width
    values = array.array('i' if width == 4 else 'h', bytes(data[start:end]))
    assert values.itemsize == width
    values.byteswap()
    data[start:end] = values.tobytes()
    open(destination, 'wb').write(bytes(data))


if __name__ == '__main__':
    if len(sys.argv) != 3:
        sys.exit('usage: c3d_to_mips.py IN_intel.c3d OUT_mips.c3d')
    main(sys.argv[1], sys.argv[2])
