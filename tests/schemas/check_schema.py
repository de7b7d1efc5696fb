#!/usr/bin/python3
"""Validates JSON files against proprio's schemas (docs/formats/schemas).

usage: check_schema.py SCHEMA_DIR SCHEMA_NAME FILE [FILE ...]
Exit 0 when every file is valid, 1 with one line per problem otherwise.
"""
import json
import pathlib
import sys

import jsonschema


def main() -> int:
    schema_dir, name, files = pathlib.Path(sys.argv[1]), sys.argv[2], sys.argv[3:]
    store = {}
    for p in schema_dir.glob("*.schema.json"):
        s = json.loads(p.read_text())
        store[s.get("$id", p.name)] = s
    schema = store[name]
    cls = jsonschema.validators.validator_for(schema)
    cls.check_schema(schema)
    resolver = jsonschema.RefResolver(base_uri=schema.get("$id", name), referrer=schema, store=store)
    validator = cls(schema, resolver=resolver, format_checker=cls.FORMAT_CHECKER)
    bad = 0
    for f in files:
        for err in validator.iter_errors(json.loads(pathlib.Path(f).read_text())):
            path = "/".join(str(x) for x in err.absolute_path)
            print(f"{f}: {path or '(root)'}: {err.message}")
            bad += 1
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
