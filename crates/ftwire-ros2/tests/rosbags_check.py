#!/usr/bin/env python3
"""An independent check of ftwire-ros2's bags, CDR bytes and message definitions, with the
`rosbags` package (pure Python; its type stores hold the official ROS 2 Humble and Jazzy
message definitions, and its reader reads rosbag2's MCAP files).

    python rosbags_check.py BAG.mcap [--expected BAG.json]

For a bag written by ftwire (`cargo run --release -p ftwire-ros2 --example write_all_types --
DIR`, or `ftwire ros2 estimate --record`), it checks:

1. the bag opens with rosbags' rosbag2 reader (MCAP, profile ros2) and every channel's
   `offered_qos_profiles` parses;
2. every message deserialises with the official Humble and with the official Jazzy type store
   (not with the bag's own schemas), to the same values, using every byte;
3. each schema (our `ros2msg` definition text), parsed by rosbags, declares for every type it
   holds the same fields, in the same order, with the same types as the official definitions
   of both distributions, and the same constants as the distribution the bag was written for
   (`distro` in the JSON, else Jazzy); a constant that only the other distribution differs in
   is reported, not failed;
4. with `--expected` (the JSON the example writes): every topic is there with its type, its
   QoS's reliability and durability, and each message's field values (names and values, the
   official field names against our structs' serde names) equal the known ones.

Prints what it checked and exits 0, or prints each mismatch and exits 1.
"""

import argparse
import dataclasses
import json
import math
import sys
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

STORES = {"humble": Stores.ROS2_HUMBLE, "jazzy": Stores.ROS2_JAZZY}


def fields_of(message):
    """The field names of a deserialised message, in declaration order: its dataclass fields
    less its constants (UPPER_CASE, as ROS names constants; fields are lower case) and rosbags'
    own `__msgtype__`."""
    return [
        f.name
        for f in dataclasses.fields(message)
        if not f.name.startswith("__") and f.name == f.name.lower()
    ]


def same(expected, actual, where, errors):
    """Compares a JSON value of our struct with rosbags' deserialised value."""
    if isinstance(expected, dict):
        if not dataclasses.is_dataclass(actual):
            errors.append(f"{where}: a message expected, got {type(actual).__name__}")
            return
        names = fields_of(actual)
        if sorted(names) != sorted(expected):
            errors.append(f"{where}: fields {names} against ours {sorted(expected)}")
            return
        for name in names:
            same(expected[name], getattr(actual, name), f"{where}.{name}", errors)
    elif isinstance(expected, list):
        if len(expected) != len(actual):
            errors.append(f"{where}: {len(actual)} elements, {len(expected)} expected")
            return
        for i, (e, a) in enumerate(zip(expected, actual)):
            same(e, a, f"{where}[{i}]", errors)
    elif isinstance(expected, bool):
        if bool(actual) is not expected or not isinstance(actual, (bool, np.bool_)):
            errors.append(f"{where}: {actual!r}, {expected!r} expected")
    elif isinstance(expected, int) and not isinstance(actual, (float, np.floating)):
        if int(actual) != expected:
            errors.append(f"{where}: {actual!r}, {expected!r} expected")
    elif isinstance(expected, (int, float)):
        if isinstance(actual, np.float32):
            ok = np.float32(expected) == actual
        else:
            ok = float(actual) == float(expected) or (
                math.isnan(float(expected)) and math.isnan(float(actual))
            )
        if not ok:
            errors.append(f"{where}: {actual!r}, {expected!r} expected")
    elif isinstance(expected, str):
        if actual != expected:
            errors.append(f"{where}: {actual!r}, {expected!r} expected")
    else:
        errors.append(f"{where}: cannot compare {expected!r}")


def same_deserialised(a, b):
    """Whether two deserialised values are equal (numpy arrays element by element)."""
    if dataclasses.is_dataclass(a):
        return all(same_deserialised(getattr(a, n), getattr(b, n)) for n in fields_of(a))
    if isinstance(a, np.ndarray):
        return a.dtype == b.dtype and np.array_equal(a, b)
    if isinstance(a, list):
        return len(a) == len(b) and all(same_deserialised(x, y) for x, y in zip(a, b))
    return a == b


def check_definition(connection, official, distro, errors, notes):
    """Our schema text, parsed by rosbags, against the official definitions."""
    ours = get_types_from_msg(connection.msgdef.data, connection.msgtype)
    for name, (consts, fields) in sorted(ours.items()):
        for store_name, store in official.items():
            if name not in store.fielddefs:
                errors.append(f"{connection.topic}: {name} is not in {store_name}'s definitions")
                continue
            want_consts, want_fields = store.fielddefs[name]
            if list(fields) != list(want_fields):
                errors.append(
                    f"{connection.topic}: {name}'s fields differ from {store_name}'s:\n"
                    f"    ours     {fields}\n    official {want_fields}"
                )
            if list(consts) != list(want_consts):
                ours_only = sorted({c[0] for c in consts} - {c[0] for c in want_consts})
                theirs_only = sorted({c[0] for c in want_consts} - {c[0] for c in consts})
                text = (
                    f"{name}'s constants differ from {store_name}'s (only ours: {ours_only}, "
                    f"only {store_name}'s: {theirs_only}, or values)"
                )
                if store_name == distro:
                    errors.append(f"{connection.topic}: {text}")
                elif text not in notes:
                    notes.append(text)
    return len(ours)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("bag", type=Path, help="the bag (.mcap)")
    parser.add_argument("--expected", type=Path, help="the known values (the example's JSON)")
    args = parser.parse_args()

    expected = json.loads(args.expected.read_text()) if args.expected else None
    distro = expected["distro"] if expected else "jazzy"
    if distro not in STORES:
        sys.exit(f"distro {distro!r}: humble or jazzy")
    official = {name: get_typestore(store) for name, store in STORES.items()}
    errors, notes = [], []
    messages, types_checked, values = 0, set(), {}

    with Reader(args.bag) as reader:
        for connection in reader.connections:
            if connection.msgtype in types_checked:
                continue
            types_checked.add(connection.msgtype)
            check_definition(connection, official, distro, errors, notes)
            if not connection.ext.offered_qos_profiles:
                errors.append(f"{connection.topic}: no offered_qos_profiles")
        for connection, _, raw in reader.messages():
            messages += 1
            decoded = {}
            for name, store in official.items():
                try:
                    decoded[name] = store.deserialize_cdr(raw, connection.msgtype)
                    # Every byte used: serialising again gives the same bytes.
                    again = store.serialize_cdr(decoded[name], connection.msgtype)
                    if bytes(again) != bytes(raw):
                        errors.append(f"{connection.topic}: {name} re-serialises differently")
                except Exception as e:  # noqa: BLE001 - any failure is a finding
                    errors.append(f"{connection.topic}: {name} cannot read it: {e}")
            if len(decoded) == 2 and not same_deserialised(decoded["humble"], decoded["jazzy"]):
                errors.append(f"{connection.topic}: Humble and Jazzy read different values")
            values.setdefault(connection.topic, (connection, decoded.get(distro)))

        if expected:
            for entry in expected["topics"]:
                topic = entry["topic"]
                if topic not in values:
                    errors.append(f"{topic}: not in the bag")
                    continue
                connection, message = values[topic]
                if connection.msgtype != entry["type"]:
                    errors.append(f"{topic}: type {connection.msgtype}, {entry['type']} expected")
                qos = connection.ext.offered_qos_profiles
                if len(qos) != 1:
                    errors.append(f"{topic}: {len(qos)} QoS profiles, 1 expected")
                else:
                    for key in ("reliability", "durability"):
                        got = getattr(qos[0], key).name.lower()
                        if got != entry[key]:
                            errors.append(f"{topic}: {key} {got}, {entry[key]} expected")
                if message is not None:
                    same(entry["value"], message, topic, errors)
            missing = len(values) - len(expected["topics"])
            if missing:
                errors.append(f"{missing} topics of the bag are not in {args.expected}")

    for note in notes:
        print(f"note: {note}")
    for error in errors:
        print(f"MISMATCH: {error}")
    print(
        f"rosbags check of {args.bag}: {messages} messages on {len(values)} topics, "
        f"{len(types_checked)} types' definitions against Humble's and Jazzy's"
        + (", values against the known ones" if expected else "")
        + f" (written for {distro}): "
        + ("ok" if not errors else f"{len(errors)} mismatches")
    )
    sys.exit(1 if errors else 0)


if __name__ == "__main__":
    main()
