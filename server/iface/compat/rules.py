"""The compatibility rules: stable codes, default severities and what each one means.

Severity says what a finding does to the verdict: an ``error`` breaks
replaceability, a ``warning`` is printed but changes neither verdict nor exit
code, ``information`` is a compatible change (NEW provides more or requires
less) that still makes the two interfaces differ. Some rules take a severity
that depends on the direction of the data (see ``docs/compat.md``); the table
gives the strictest one.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..model.diagnostics import Severity

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFORMATION


@dataclass(frozen=True, slots=True)
class Rule:
    """One rule: its code, strictest severity, the set it belongs to and a summary."""

    code: str
    severity: Severity
    area: str
    summary: str


_TABLE: list[tuple[str, Severity, str, str]] = [
    # M, N: topics
    ("published-removed", E, "N", "OLD publishes a topic that NEW does not: its subscribers starve."),
    ("published-added", I, "N", "NEW publishes one more topic."),
    ("subscribed-added", E, "M", "NEW subscribes a topic OLD did not: it needs an input OLD did not."),
    ("subscribed-removed", I, "M", "NEW subscribes one topic fewer."),
    ("topic-type-changed", E, "M/N", "A topic carries a different message type."),
    ("qos-incompatible", E, "M/N", "A QoS change after which a peer that matched OLD no longer matches."),
    ("qos-changed", I, "M/N", "A QoS change that does not affect matching."),
    # S, A: services and actions
    ("service-removed", E, "S", "OLD provides a service that NEW does not."),
    ("service-added", I, "S", "NEW provides one more service."),
    ("service-call-added", E, "S", "NEW calls a service OLD did not call."),
    ("service-call-removed", I, "S", "NEW calls one service fewer."),
    ("service-type-changed", E, "S", "A service name bound to a different service type."),
    ("action-removed", E, "A", "OLD provides an action that NEW does not."),
    ("action-added", I, "A", "NEW provides one more action."),
    ("action-call-added", E, "A", "NEW calls an action OLD did not call."),
    ("action-call-removed", I, "A", "NEW calls one action fewer."),
    ("action-type-changed", E, "A", "An action name bound to a different action type."),
    # P: parameters
    ("parameter-added-required", E, "P", "A new parameter without a default: every deployment must now set it."),
    ("parameter-default-removed", E, "P", "A parameter that lost its default: deployments that relied on it must now set it."),
    ("parameter-added", I, "P", "A new parameter with a default."),
    ("parameter-removed", I, "P", "NEW needs one parameter fewer."),
    ("parameter-renamed", E, "P", "A parameter id with a new name: ROS 2, PX4 and ArduPilot set parameters by name."),
    ("parameter-type-changed", E, "P", "A parameter whose type does not accept every value the old type did."),
    ("parameter-type-widened", I, "P", "A parameter whose type accepts more values."),
    # Σ: state
    ("state-lost", E, "Σ", "A state variable of OLD that NEW does not have: its value is lost on hand-over."),
    ("state-type-changed", E, "Σ", "A state variable whose value cannot be carried over to the new type."),
    ("state-type-widened", I, "Σ", "A state variable whose new type holds every old value."),
    ("state-added", I, "Σ", "A new state variable with an initial value."),
    ("state-needs-initial", W, "Σ", "A new state variable without a default: the hand-over must give it a value."),
    # Δ: diagnostics
    ("diagnostics-removed", E, "Δ", "A diagnostics service of OLD that NEW does not have."),
    ("diagnostics-added", I, "Δ", "A new diagnostics service."),
    ("diagnostics-type-changed", E, "Δ", "A diagnostics service name bound to a different service type."),
    # definitions
    ("definition-removed", E, "types", "A struct, union, exception, message, service or action that NEW does not define."),
    ("definition-added", I, "types", "A new definition."),
    ("definition-kind-changed", E, "types", "A name that now defines a different kind of thing."),
    ("enum-removed", W, "types", "An enum that NEW does not define (fields that use it are reported too)."),
    ("enum-value-removed", E, "types", "An enum value that NEW does not have."),
    ("enum-value-added", I, "types", "A new enum value."),
    ("enum-value-renamed", W, "types", "An enum value with a new name for the same number."),
    ("typedef-removed", W, "types", "A typedef that NEW does not define."),
    ("typedef-changed", E, "types", "A typedef that stands for a different type."),
    ("const-removed", W, "types", "A constant that NEW does not define."),
    ("const-type-changed", W, "types", "A constant of a different type."),
    ("const-value-changed", W, "types", "A constant with a different value."),
    ("const-added", I, "types", "A new constant."),
    # fields (struct bodies, sections, arguments, exceptions)
    ("field-removed", E, "fields", "A field that NEW does not have."),
    ("field-added", I, "fields", "A new optional field (or, without ids, any new field: then an error)."),
    ("required-field-added", E, "fields", "A new required field that senders built against OLD do not fill."),
    ("field-id-inserted", E, "fields", "A new field id below the highest old id (Thrift: added in the middle)."),
    ("field-type-changed", E, "fields", "A field of another type (Thrift: only identical types are compatible)."),
    ("field-requiredness-changed", E, "fields", "A field that became required or stopped being required."),
    ("field-optionality-changed", I, "fields", "A field moved between default and optional requiredness."),
    ("field-renamed", W, "fields", "A field id with a new name (without ids: an error, the ROS 2 type changes)."),
    ("field-moved", E, "fields", "A field at another position in a body without ids: the wire layout changes."),
    ("field-keying-changed", E, "fields", "A body that gained or lost field ids."),
    ("default-changed", W, "fields", "A field or parameter with a different default value."),
    ("unit-changed", E, "fields", "A field or parameter with a different unit."),
    ("range-narrowed", E, "fields", "A range that no longer admits every value it did (where the component receives)."),
    ("range-widened", I, "fields", "A range that admits more values (where the component receives)."),
    # services (Thrift functions, sections), actions
    ("function-removed", E, "services", "A function that NEW's service does not have."),
    ("function-added", I, "services", "A new function."),
    ("return-type-changed", E, "services", "A function that returns a different type."),
    ("oneway-changed", E, "services", "A function that became oneway or stopped being oneway."),
    ("extends-changed", E, "services", "A service that extends a different service, or none."),
    ("extends-added", I, "services", "A service that now extends another."),
    ("service-form-changed", E, "services", "A service changed between Thrift functions and request/response."),
    # headers
    ("namespace-removed", W, "headers", "A namespace scope that NEW does not declare."),
    ("namespace-changed", W, "headers", "A namespace with a different name."),
    ("namespace-added", I, "headers", "A new namespace scope."),
    # system (with --system)
    ("system-conflict", E, "system", "An element NEW adds that clashes with another component of the system."),
    # the safety net
    ("other-change", I, "any", "A difference in the canonical form that no finer rule names."),
]

#: code -> Rule
RULES: dict[str, Rule] = {code: Rule(code, sev, area, summary) for code, sev, area, summary in _TABLE}


def rule(code: str) -> Rule:
    """The rule with ``code`` (KeyError for an unknown code)."""
    return RULES[code]
