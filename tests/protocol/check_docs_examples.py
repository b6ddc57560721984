#!/usr/bin/python3
"""Validates every JSON example of docs/protocol.md against the JSON Schemas in protocol/schema.

An example is a fenced ```json block preceded (blank lines allowed) by an annotation comment:
  <!-- schema: NAME -->          NAME is METHOD.params | METHOD.result | METHOD.request |
                                 METHOD.reply | error.reply | surface | event | request
  <!-- bad-request: CODE POINTER -->  a request the server must reject with CODE at POINTER
                                 (checked by the C++ test test_docs_examples.cpp; here it
                                 must be JSON unless CODE is -32700)
Also checks that every schema file is a valid draft 2020-12 schema, that every method of the
protocol has a documented request and reply example, and that no ```json block is left
unannotated.

Usage: check_docs_examples.py docs/protocol.md protocol/schema
"""
import json
import pathlib
import re
import sys

import jsonschema

BASE = "https://polycut.dev/protocol/1/"
METHODS = ["hello", "load_scene", "reset", "pause", "resume", "step", "set_rate", "apply_force",
           "remove_force", "grab", "move_grab", "release", "cut", "scalpel", "end_stroke",
           "get_surface", "get_stats", "shutdown", "tool_create", "tool_move", "tool_remove"]
ANNOTATION = re.compile(r"<!--\s*(schema|bad-request):\s*(.*?)\s*-->")


def load_schemas(directory):
    store = {}
    for path in sorted(pathlib.Path(directory).glob("*.json")):
        schema = json.loads(path.read_text())
        jsonschema.Draft202012Validator.check_schema(schema)
        if schema.get("$id") != BASE + path.name:
            raise SystemExit(f"{path}: $id must be {BASE + path.name}")
        store[schema["$id"]] = schema
    return store


def schema_for(name):
    """The schema an annotation NAME refers to."""
    if name in ("surface", "event", "request"):
        return {"$ref": BASE + name + ".json"}
    if name == "error.reply":
        return {"allOf": [{"$ref": BASE + "response.json"}, {"required": ["error"]}]}
    method, _, part = name.partition(".")
    if method not in METHODS:
        raise KeyError(f"unknown schema name {name!r}")
    ref = BASE + method + ".json#/$defs/"
    if part in ("params", "result"):
        return {"$ref": ref + part}
    if part == "request":
        return {"allOf": [{"$ref": BASE + "request.json"},
                          {"properties": {"method": {"const": method},
                                          "params": {"$ref": ref + "params"}}}]}
    if part == "reply":
        return {"allOf": [{"$ref": BASE + "response.json"}, {"required": ["result"]},
                          {"properties": {"result": {"$ref": ref + "result"}}}]}
    raise KeyError(f"unknown schema name {name!r}")


def examples(markdown):
    """(line, kind, argument, text) for every ```json block; kind None if unannotated."""
    lines = markdown.splitlines()
    pending = None
    i = 0
    while i < len(lines):
        line = lines[i]
        match = ANNOTATION.search(line)
        if match:
            pending = (match.group(1), match.group(2))
        elif line.strip().startswith("```json"):
            start = i + 1
            j = start
            while j < len(lines) and not lines[j].strip().startswith("```"):
                j += 1
            text = "\n".join(lines[start:j])
            kind, arg = pending if pending else (None, None)
            yield start, kind, arg, text
            pending = None
            i = j
        elif line.strip() and pending and not line.strip().startswith("<!--"):
            pending = None  # an annotation applies to the next block only
        i += 1


def main():
    doc_path, schema_dir = sys.argv[1], sys.argv[2]
    store = load_schemas(schema_dir)
    resolver_store = dict(store)
    failures = []
    seen = set()
    count = 0
    for line, kind, arg, text in examples(pathlib.Path(doc_path).read_text()):
        count += 1
        where = f"{doc_path}:{line}"
        if kind is None:
            failures.append(f"{where}: ```json block without a schema/bad-request annotation")
            continue
        if kind == "bad-request":
            code = arg.split()[0]
            if code != "-32700":
                try:
                    json.loads(text)
                except json.JSONDecodeError as e:
                    failures.append(f"{where}: bad-request example is not JSON: {e}")
            continue
        seen.add(arg)
        try:
            instance = json.loads(text)
        except json.JSONDecodeError as e:
            failures.append(f"{where}: not JSON: {e}")
            continue
        try:
            schema = schema_for(arg)
        except KeyError as e:
            failures.append(f"{where}: {e}")
            continue
        resolver = jsonschema.RefResolver(base_uri=BASE, referrer=schema, store=resolver_store)
        validator = jsonschema.Draft202012Validator(schema, resolver=resolver)
        errors = sorted(validator.iter_errors(instance), key=lambda e: list(e.path))
        for error in errors:
            path = "/" + "/".join(str(p) for p in error.absolute_path)
            failures.append(f"{where}: [{arg}] {path}: {error.message}")
    for method in METHODS:
        for part in ("request", "reply"):
            if f"{method}.{part}" not in seen:
                failures.append(f"{doc_path}: no example annotated '{method}.{part}'")
    for needed in ("error.reply", "surface", "event"):
        if needed not in seen:
            failures.append(f"{doc_path}: no example annotated '{needed}'")
    if failures:
        print("\n".join(failures))
        print(f"FAILED: {len(failures)} problems in {count} examples")
        return 1
    print(f"ok: {count} examples, {len(store)} schemas")
    return 0


if __name__ == "__main__":
    sys.exit(main())
