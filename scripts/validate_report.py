#!/usr/bin/python3
"""Validates report.json files against schemas/report.schema.json with Debian's python3-jsonschema.

Usage: /usr/bin/python3 scripts/validate_report.py SCHEMA REPORT.json [REPORT.json ...]
Prints one line per invalid file (file: path in the document: message) and exits 1 when any is
invalid, 2 when the schema or a file cannot be read.
"""
import json
import sys

import jsonschema


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    try:
        with open(sys.argv[1], encoding="utf-8") as f:
            schema = json.load(f)
        validator = jsonschema.Draft7Validator(schema)
    except (OSError, ValueError, jsonschema.SchemaError) as error:
        print(f"{sys.argv[1]}: {error}")
        sys.exit(2)
    invalid = 0
    for path in sys.argv[2:]:
        try:
            with open(path, encoding="utf-8") as f:
                document = json.load(f)
        except (OSError, ValueError) as error:
            print(f"{path}: {error}")
            sys.exit(2)
        for error in sorted(validator.iter_errors(document), key=lambda e: list(e.path))[:5]:
            where = "/".join(str(p) for p in error.path) or "(root)"
            print(f"{path}: {where}: {error.message[:300]}")
            invalid += 1
    sys.exit(1 if invalid else 0)


if __name__ == "__main__":
    main()
