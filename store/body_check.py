"""Checking an event's body against its kind's JSON Schema (store/schemas/<kind>.json).

The schemas are compiled by fastjsonschema into plain Python functions, once per kind and only
when a kind is first seen, so that commands which never append start fast. fastjsonschema reads
our 2020-12 schemas with its draft 2019-09 rules; the keywords the schemas use (type, enum,
required, properties, items as one schema, min/max, exclusiveMinimum (a number in both), minLength,
pattern, oneOf, $ref to $defs) mean the same in both drafts.
"""

from __future__ import annotations

from typing import Any, Callable, Iterable, cast

import re

import fastjsonschema
from fastjsonschema.draft04 import DOLLAR_FINDER

from .canonical import PLAIN_FLOAT
from .describe import json_type, show
from .kinds import SCHEMAS

Validator = Callable[..., Any]
_compiled: dict[str, Validator] = {}


def validator(kind: str) -> Validator:
    """The compiled schema of a known kind (KeyError for an unknown one)."""
    found = _compiled.get(kind)
    if found is None:
        found = _compiled[kind] = fastjsonschema.compile(SCHEMAS[kind])
    return found


def body_ok(kind: str, body: Any) -> bool:
    """Does the body satisfy its schema? The fast yes/no of the append path: the kind's quick
    check first (below), fastjsonschema when that cannot say yes."""
    check = _first_checks.get(kind)
    if check is None:
        check = _first_checks[kind] = quick(kind) or _cannot_tell
    try:
        if check(body):
            return True
    except RecursionError:  # a tree nested deeper than the quick check's recursion goes
        pass
    try:
        (_compiled.get(kind) or validator(kind))(body)
    except (fastjsonschema.JsonSchemaValueException, RecursionError):
        return False
    return True


def body_problem(kind: str, body: Any) -> tuple[str, str] | None:
    """(field, sentence) for the first schema rule the body breaks, or None.

    The field is the failing path ("body.speed_mps", "body.facts[1]"), the sentence names the
    kind, the path, the rule and (briefly) the value, for the person reading the quarantine.
    """
    try:
        validator(kind)(body, name_prefix="body")
    except fastjsonschema.JsonSchemaValueException as exc:
        shown = f"{json_type(exc.value)} {show(exc.value)}"
        return cast(str, exc.name), f"{kind} {exc.message} (schema rule {exc.rule}), got {shown}"
    except RecursionError:
        return "body", f"{kind} body is nested too deeply to check"
    return None


# --- a faster yes for the common case -----------------------------------------------------------
#
# fastjsonschema's code is general (it builds two sets per object, accepts Decimal and
# subclasses, keeps definitions for its messages) and is most of the cost of checking an event.
# For each kind, `quick` compiles the schema's flat properties into one expression that answers
# True only when the body surely satisfies the schema: exact built-in types, and only the
# keywords below, patterns (compiled as fastjsonschema compiles them), nested objects with their
# own required and properties, a $ref to one of the schema's $defs (recursive, as a vehicle's
# proof tree is) and a oneOf whose branches are of distinct types (then "exactly one holds" is
# "some holds"). Anything else it answers False for, and fastjsonschema decides as before, so
# the quick check can make an append faster but can never let a body through that the schema
# refuses (tests/store/test_store_body_validation.py checks this on generated bodies).

_ANNOTATIONS = frozenset(("description", "title", "$comment", "examples", "$schema", "$id", "x-src-roles"))
_TYPE_TESTS = {
    # exact types only: a subclass, a Decimal or a float 'integer' goes to fastjsonschema
    "string": "type({v}) is str",
    "number": "(type({v}) is float or type({v}) is int)",
    "integer": "type({v}) is int",
    "boolean": "({v} is True or {v} is False)",
    "null": "{v} is None",
    "array": "type({v}) is list",
    "object": "type({v}) is dict",
}
_KEYWORDS_BY_TYPE = {  # keywords the quick check understands, by the JSON type they constrain
    "string": {"minLength": "len({v}) >= {n}", "maxLength": "len({v}) <= {n}"},
    "number": {"minimum": "{v} >= {n}", "maximum": "{v} <= {n}", "exclusiveMinimum": "{v} > {n}"},
    "integer": {"minimum": "{v} >= {n}", "maximum": "{v} <= {n}"},
    "array": {"minItems": "len({v}) >= {n}", "maxItems": "len({v}) <= {n}"},
}


class _Unsupported(Exception):
    """A schema uses something the quick check does not model; fastjsonschema decides it."""


# The plain check's number: an int, or a float orjson writes as the canonical form does (PLAIN_FLOAT).
# An int is plain within the 64 bits orjson writes (signed or unsigned); it refuses a wider one.
_INT_LOW, _INT_HIGH = -(1 << 63), (1 << 64) - 1
_PLAIN_NUMBER = (f"((type({{v}}) is int and {_INT_LOW} <= {{v}} <= {_INT_HIGH}) "
                 f"or (type({{v}}) is float and ({PLAIN_FLOAT.format(x='{v}')})))")


class _Writer:
    """Python source for the quick check of one kind, with its helpers and constants. With
    plain=True, the plain check instead (see `plain`): numbers as _PLAIN_NUMBER, and no value the
    schema does not name."""

    def __init__(self, plain: bool = False) -> None:
        self.lines: list[str] = []
        self.constants: dict[str, Any] = {}
        self.plain = plain
        self.defs: dict[str, Any] = {}
        self.refs: dict[str, str] = {}  # a $ref's target -> the name of its helper

    def constant(self, value: Any) -> str:
        name = f"_c{len(self.constants)}"
        self.constants[name] = value
        return name

    def test(self, schema: Any, v: str) -> str:
        """An expression over variable `v` that is true only if `v` satisfies `schema`."""
        if not isinstance(schema, dict):
            raise _Unsupported
        if "$ref" in schema:
            return f"{self.ref(schema)}({v})"
        if "oneOf" in schema:
            return self.one_of(schema, v)
        if schema.get("type") == "object" and not self.plain:
            return f"{self.object(schema)}({v})"
        known = _ANNOTATIONS | {"type", "enum", "items", "pattern"} | {k for ks in _KEYWORDS_BY_TYPE.values() for k in ks}
        if set(schema) - known:
            raise _Unsupported
        if "pattern" in schema and schema.get("type") != "string":
            raise _Unsupported
        types = schema.get("type")
        enum = schema.get("enum")
        if types is None and enum is not None:
            types = "string"  # only all-string enums are modelled (checked below)
        if types is None:
            raise _Unsupported
        if isinstance(types, str):
            types = [types]
        if not isinstance(types, list) or not types or any(t not in _TYPE_TESTS for t in types):
            raise _Unsupported
        if enum is not None and not (isinstance(enum, list) and enum and all(type(e) is str for e in enum)):
            raise _Unsupported
        branches = []
        if self.plain and ("object" in types or ("array" in types and "items" not in schema)):
            raise _Unsupported  # values inside that nothing here looks at: the walk must see them
        for json_type in types:
            type_test = _PLAIN_NUMBER if self.plain and json_type == "number" else _TYPE_TESTS[json_type]
            parts = [type_test.format(v=v)]
            for keyword, template in _KEYWORDS_BY_TYPE.get(json_type, {}).items():
                if keyword in schema:
                    bound = schema[keyword]
                    if type(bound) is not int and type(bound) is not float:
                        raise _Unsupported
                    parts.append(template.format(v=v, n=repr(bound)))
            if "pattern" in schema:  # fastjsonschema's own reading of it: search, with $ as \\Z
                if type(schema["pattern"]) is not str:
                    raise _Unsupported
                regex = re.compile(DOLLAR_FINDER.sub(r"\\Z", schema["pattern"]))
                parts.append(f"{self.constant(regex)}.search({v}) is not None")
            if enum is not None:
                if json_type != "string":
                    continue  # an all-string enum admits no value of another type
                parts.append(f"{v} in {self.constant(frozenset(enum))}")
            if "items" in schema and json_type == "array":
                parts.append(f"{self.items(schema['items'])}({v})")
            branches.append(" and ".join(parts))
        if not branches:
            raise _Unsupported
        return "(" + " or ".join(f"({b})" for b in branches) + ")"

    def extras(self, named: Iterable[str]) -> str:
        """The name of a helper that checks a body's values under names its schema does not give
        (its additional properties, which the schema takes whatever they hold): each a scalar
        orjson writes as the canonical form does. A simulation's road users report more than the
        schema names (a lane, an acceleration), and without this every one of their states left
        the fast lane."""
        name = f"_extras{len(self.lines)}"
        scalar = f"type(x) is str or type(x) is bool or x is None or {_PLAIN_NUMBER.format(v='x')}"
        self.lines += [f"def {name}(body):", f"    for name in body.keys() - {self.constant(frozenset(named))}:",
                       "        x = body[name]", f"        if not ({scalar}):",
                       "            return False", "    return True"]
        return name

    def ref(self, schema: dict) -> str:
        """The name of a helper that checks a value against the definition a `$ref` names (one of
        the schema's own $defs; recursive where the definition is, as a proof's children are)."""
        if set(schema) - _ANNOTATIONS != {"$ref"} or self.plain:
            raise _Unsupported  # plain: a definition is an object, whose insides need the walk
        target = schema["$ref"]
        if target not in self.refs:
            if not (isinstance(target, str) and target.startswith("#/$defs/")):
                raise _Unsupported
            definition = self.defs.get(target[len("#/$defs/"):])
            if not isinstance(definition, dict) or definition.get("type") != "object":
                raise _Unsupported
            self.refs[target] = name = f"_def{len(self.refs)}"
            try:
                self.object(definition, name)
            except _Unsupported:
                del self.refs[target]  # no helper of that name was written
                raise
        return self.refs[target]

    def one_of(self, schema: dict, v: str) -> str:
        """oneOf over branches of distinct JSON types: a value of exact built-in type can be of only
        one branch's type, so 'exactly one branch holds' is 'some branch holds'. Branches whose
        types could meet (number and integer, or a branch without a type) are not modelled."""
        branches = schema["oneOf"]
        if set(schema) - _ANNOTATIONS != {"oneOf"} or not isinstance(branches, list) or not branches:
            raise _Unsupported
        seen: set[str] = set()
        for branch in branches:
            types = branch.get("type") if isinstance(branch, dict) else None
            types = [types] if isinstance(types, str) else types
            if not isinstance(types, list) or not types or any(t not in _TYPE_TESTS for t in types):
                raise _Unsupported
            named = {"number" if t == "integer" else t for t in types}
            if named & seen or len(named) != len(types):
                raise _Unsupported
            seen |= named
        return "(" + " or ".join(self.test(branch, v) for branch in branches) + ")"

    def object(self, schema: dict, name: str | None = None) -> str:
        """The name of a helper that checks a value against an object schema with its own
        required and properties (not for the plain check: values inside need the walk)."""
        if set(schema) - (_ANNOTATIONS | {"type", "required", "properties", "additionalProperties"}):
            raise _Unsupported
        if schema.get("additionalProperties", True) is not True:
            raise _Unsupported
        required, properties = schema.get("required", []), schema.get("properties", {})
        if not isinstance(required, list) or not isinstance(properties, dict):
            raise _Unsupported
        name = name or f"_object{len(self.lines)}"
        missing = self.constant(object())
        lines = [f"def {name}(body):", "    if type(body) is not dict:", "        return False", "    get = body.get"]
        for field in required:
            if type(field) is not str:
                raise _Unsupported
            if field not in properties:
                lines += [f"    if {field!r} not in body:", "        return False"]
        for field, subschema in properties.items():
            test = self.test(subschema, "v")
            lines.append(f"    v = get({field!r}, {missing})")
            if field in required:
                lines += [f"    if v is {missing} or not {test}:", "        return False"]
            else:
                lines += [f"    if v is not {missing} and not {test}:", "        return False"]
        self.lines += lines + ["    return True"]
        return name

    def items(self, schema: Any) -> str:
        """The name of a helper that checks every element of a list against `schema`."""
        name = f"_items{len(self.lines)}"
        self.lines += [f"def {name}(values):", "    for x in values:",
                       f"        if not {self.test(schema, 'x')}:", "            return False", "    return True"]
        return name

    def body(self, schema: dict) -> str:
        """The quick check of an object schema with flat properties, as source."""
        if set(schema) - (_ANNOTATIONS | {"type", "required", "properties", "additionalProperties", "$defs"}):
            raise _Unsupported
        defs = schema.get("$defs", {})
        self.defs = defs if isinstance(defs, dict) else {}
        if schema.get("type") != "object" or schema.get("additionalProperties", True) is not True:
            raise _Unsupported
        required = schema.get("required", [])
        properties = schema.get("properties", {})
        if not isinstance(required, list) or not isinstance(properties, dict):
            raise _Unsupported
        missing = self.constant(object())
        lines = ["def quick(body):", "    if type(body) is not dict:", "        return False",
                 "    get = body.get"]
        if self.plain:  # every value must be one of the properties checked: count the others
            lines.append(f"    unnamed = len(body) - {sum(name in properties for name in required)}")
        for name in required:
            if name not in properties:
                if self.plain:
                    raise _Unsupported  # a value of no known type in every body: never plain
                lines.append(f"    if {name!r} not in body:")
                lines.append("        return False")
        for name, subschema in properties.items():
            try:
                test = self.test(subschema, "v")
            except _Unsupported:
                test = "False"  # present: let fastjsonschema judge it; absent: nothing to check
            lines.append(f"    v = get({name!r}, {missing})")
            if name in required:
                lines.append(f"    if v is {missing} or not {test}:")
                lines.append("        return False")
            else:
                lines.append(f"    if v is not {missing}:")
                lines.append(f"        if not {test}:")
                lines.append("            return False")
                if self.plain:
                    lines.append("        unnamed -= 1")
        if self.plain:  # a value under a name the schema does not give must be a plain scalar
            lines.append(f"    return unnamed == 0 or {self.extras(properties)}(body)")
        else:
            lines.append("    return True")
        return "\n".join(self.lines + lines)


def quick_source(schema: dict, plain: bool = False) -> str | None:
    """The source of a kind's quick check, or with plain=True its plain check (for reading and
    tests), None if it has none."""
    try:
        return _Writer(plain).body(schema)
    except _Unsupported:
        return None


def _compile_quick(schema: dict, plain: bool = False) -> Callable[[Any], bool] | None:
    writer = _Writer(plain)
    try:
        source = writer.body(schema)
    except _Unsupported:
        return None
    namespace: dict[str, Any] = dict(writer.constants)
    exec(compile(source, "<quick body check>", "exec"), namespace)  # our own generated source
    return namespace["quick"]


def quick(kind: str) -> Callable[[Any], bool] | None:
    """The quick check of a known kind, None where its schema has no flat form
    (KeyError for an unknown kind)."""
    if kind not in _quick:
        _quick[kind] = _compile_quick(SCHEMAS[kind])
    return _quick[kind]


_quick: dict[str, Callable[[Any], bool] | None] = {}
_first_checks: dict[str, Callable[[Any], bool]] = {}  # quick check, or _cannot_tell where none


# --- the plain check: valid, and written by orjson as canonical_json writes it ------------------
#
# The append path's fast lane (envelope.plain_event) needs two answers for a body: does it satisfy
# its schema (body_ok), and does orjson write it as the canonical form does (canonical's
# _same_in_orjson walk)? For a body that holds only the properties its schema names, with flat
# values, one generated function answers both at once: the quick check with numbers narrowed to
# ints and the floats both writers spell alike, and no value the schema does not name. Whatever it
# answers False for goes to body_ok and the walk, so it can only make the lane faster, never wider.

_plain: dict[str, Callable[[Any], bool]] = {}


def plain_body(kind: str) -> Callable[[Any], bool]:
    """The kind's plain check (a body it says yes to satisfies the schema and holds only values
    orjson writes canonically), or one that always says no where the schema has no flat form
    (KeyError for an unknown kind)."""
    found = _plain.get(kind)
    if found is None:
        found = _plain[kind] = _compile_quick(SCHEMAS[kind], plain=True) or _cannot_tell
    return found


def _cannot_tell(body: Any) -> bool:
    return False
