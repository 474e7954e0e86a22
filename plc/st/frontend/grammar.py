"""blark's grammar (TwinCAT's flavour of IEC 61131-3) extended to the IEC constructs it lacks,
and the transformer that turns the extensions into blark's own tree nodes.

Each extension names the clause of IEC 61131-3 (2nd edition; 3rd edition where marked):

- the exponent ``**`` as its own level between the unary operators and ``*``/``/``/``MOD``,
  left-associative (3rd ed. 7.3.2, Table 71);
- CONFIGURATION, RESOURCE ... ON, TASK and PROGRAM ... WITH (2.7; its nodes stay lark trees,
  read by :mod:`plc.st.runtime.task`);
- several types in one ``TYPE ... END_TYPE`` (2.3.3.1, B.1.3.3);
- VAR_TEMP in a FUNCTION (3rd ed. 6.6.2.2, Table 19);
- the standard functions that share their name with an operator, ``MOD(a, b)``, ``AND(...)``,
  ``OR(...)``, ``XOR(...)`` (2.5.1.5.2, 2.5.1.5.3);
- ``&`` for AND (3.3.1, Table 55);
- typed literals ``STRING#'text'`` (3rd ed. 6.3.3) and ``Color#Green`` in an expression (2.3.3.1);
- CASE labels that are constant expressions (3rd ed. 7.3.3.4.2);
- ``REF_TO`` (3rd ed. 6.4.4.10), and ``REFERENCE`` as an ordinary name (it is no IEC keyword),
  as TwinCAT's other words that IEC does not reserve (AND_THEN, OR_ELSE, FUNCTIONBLOCK, PROPERTY,
  UNION, VAR_INST, VAR_STAT and their END_ words);
- partial access ``w.%X3``, ``w.%B1`` (3rd ed. 6.6.1.3; ``w.3`` blark reads already).
"""

from __future__ import annotations

__all__ = ["RefTo", "Transformer", "extended"]

import dataclasses
from typing import Any

import blark.transform as tf
import lark

_CONFIGURATION = r"""
configuration_declaration: _CONFIGURATION IDENTIFIER _configuration_body _END_CONFIGURATION ";"*
_configuration_body: [ global_var_declarations ] resource_declaration+
resource_declaration: _RESOURCE IDENTIFIER _ON IDENTIFIER _resource_body _END_RESOURCE ";"*
_resource_body: [ global_var_declarations ] task_configuration* program_configuration*
task_configuration: _TASK IDENTIFIER "(" task_initialization ( "," task_initialization )* ")" ";"+
task_initialization: IDENTIFIER ":=" expression
program_configuration: _PROGRAM IDENTIFIER [ _WITH IDENTIFIER ] ":" IDENTIFIER ";"+
_CONFIGURATION: /\bCONFIGURATION\b/i
_END_CONFIGURATION: /\bEND_CONFIGURATION\b/i
_RESOURCE: /\bRESOURCE\b/i
_END_RESOURCE: /\bEND_RESOURCE\b/i
_ON: /\bON\b/i
_TASK: /\bTASK\b/i
_WITH: /\bWITH\b/i
"""

_ADDED = r"""
type_block: _TYPE [ access_specifier ] _type_declaration _more_types ";"* _END_TYPE ";"*
_more_types: ( ";"+ _type_declaration )+
operator_call: OPERATOR_FUNCTION "(" [ param_assignment ( "," param_assignment )* ] ")"
OPERATOR_FUNCTION: /\b(AND|OR|XOR|MOD)\b/i
typed_enum_value: TYPED_ENUM_VALUE
TYPED_ENUM_VALUE: /(?!BOOL#)[A-Za-z_][A-Za-z0-9_]*#[A-Za-z_][A-Za-z0-9_]*/i
_STRING_TYPE: /\bSTRING#/i
_WSTRING_TYPE: /\bWSTRING#/i
REF_TO: /\bREF_TO\b/i
PARTIAL_ACCESS: /%[XBWDL][0-9]+/i
"""

_EDITS = [
    (  # ** between the unary operators and * / MOD
        "expression_term: unary_expression ( MULTIPLY_OPERATOR unary_expression )*",
        "expression_term: power_expression ( MULTIPLY_OPERATOR power_expression )*\n"
        "power_expression: unary_expression ( POWER_OPERATOR unary_expression )*\n"
        'POWER_OPERATOR: "**"',
    ),
    (
        "_library_element_declaration: data_type_declaration",
        "_library_element_declaration: data_type_declaration\n"
        "                            | type_block\n"
        "                            | configuration_declaration",
    ),
    (
        "?function_var_block: input_declarations",
        "?function_var_block: temp_var_decls\n | input_declarations",
    ),
    (
        "?primary_expression: parenthesized_expression",
        "?primary_expression: parenthesized_expression\n | operator_call\n | typed_enum_value",
    ),
    ("LOGICAL_AND: _AND", 'LOGICAL_AND: _AND\n | "&"'),
    (
        "string_literal: SINGLE_BYTE_CHARACTER_STRING\n"
        "              | DOUBLE_BYTE_CHARACTER_STRING",
        "string_literal: _STRING_TYPE? SINGLE_BYTE_CHARACTER_STRING\n"
        "              | _WSTRING_TYPE? DOUBLE_BYTE_CHARACTER_STRING",
    ),
    (
        "?case_list_element: subrange\n"
        "                  | integer_literal\n"
        "                  | bit_string_literal\n"
        "                  | boolean_literal\n"
        "                  | enumerated_value\n"
        "                  | symbolic_variable",
        "?case_list_element: subrange\n                  | expression",
    ),
    ("indirection_type: REFERENCE_TO", "indirection_type: REF_TO\n                | REFERENCE_TO"),
    ("|READ_WRITE|REFERENCE|REPEAT|", "|READ_WRITE|REPEAT|"),
    # TwinCAT's words that are no IEC keywords may name a variable too
    ("(ABSTRACT|ACTION|AND|AND_THEN|", "(ABSTRACT|ACTION|AND|"),
    ("|END_FUNCTIONBLOCK|", "|"),
    ("|END_PROPERTY|", "|"),
    ("|END_UNION|", "|"),
    ("|FUNCTIONBLOCK|", "|"),
    ("|OR|OR_ELSE|", "|OR|"),
    ("|PROPERTY|", "|"),
    ("|UNION|", "|"),
    ("|VAR_INST|VAR_IN_OUT|VAR_OUTPUT|VAR_STAT|", "|VAR_IN_OUT|VAR_OUTPUT|"),
    (
        'field_selector: [ DEREFERENCED ] "." ( variable_name | INTEGER )',
        'field_selector: [ DEREFERENCED ] "." ( variable_name | INTEGER | PARTIAL_ACCESS )',
    ),
]
"""(blark's text, its replacement): each must be found once in blark's grammar."""


def extended(grammar: str) -> str:
    """blark's grammar with the IEC extensions.

    Raises:
        RuntimeError: blark's grammar is not the one these edits were written for.
    """
    for old, new in _EDITS:
        if grammar.count(old) != 1:
            raise RuntimeError("blark's grammar changed: pin the version pyproject.toml names")
        grammar = grammar.replace(old, new)
    return grammar + _CONFIGURATION + _ADDED


@dataclasses.dataclass
class RefTo(tf.IndirectionType):
    """IEC's ``REF_TO`` (3rd ed. 6.4.4.10), apart from TwinCAT's ``REFERENCE TO``."""


def _indirection(*tokens: lark.Token) -> tf.IndirectionType:
    if tokens and str(tokens[0]).upper() == "REF_TO":
        return RefTo(pointer_depth=0, reference=True)
    return tf.IndirectionType.from_lark(*tokens)


def _type_block(access: Any, *declarations: Any) -> list[tf.DataTypeDeclaration]:
    """``TYPE a : ...; b : ...; END_TYPE`` as one declaration per type."""
    found = []
    for declaration in declarations:
        item = tf.DataTypeDeclaration(declaration=declaration, access=access)
        item.meta = declaration.meta
        found.append(item)
    return found


def _operator_call(name: lark.Token, *params: Any) -> tf.FunctionCall:
    """``MOD(a, b)``: a call of the standard function named like the operator."""
    return tf.FunctionCall.from_lark(tf.SimpleVariable(name=name, dereferenced=False), *params)


def _typed_enum_value(token: lark.Token) -> tf.EnumeratedValue:
    """``Color#Green``."""
    type_name, _, value = str(token).partition("#")
    start = token.start_pos or 0
    name = lark.Token("IDENTIFIER", value, start + len(type_name) + 1, token.line, token.column)
    return tf.EnumeratedValue(lark.Token("IDENTIFIER", type_name), name, None)


class Transformer(tf.GrammarTransformer):
    """blark's transformer with the extensions as blark's nodes: ``**`` a binary operation,
    a TYPE block of several types a list of declarations, ``MOD(...)`` a function call,
    ``Color#Green`` an enumerated value, ``REF_TO`` a :class:`RefTo`."""

    power_expression = tf._annotator_wrapper(tf.BinaryOperation.from_lark)
    indirection_type = tf._annotator_wrapper(_indirection)
    type_block = tf._annotator_wrapper(_type_block)
    operator_call = tf._annotator_wrapper(_operator_call)
    typed_enum_value = tf._annotator_wrapper(_typed_enum_value)
