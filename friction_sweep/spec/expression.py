"""The text of a quantity ("40 kN/m", "4.9 m/s^2", "3000 rev/min") read by its own small grammar before pint
sees any of it: pint evaluates what its tokenizer finds as Python numbers, so `(((9**99)**99)**99)**99 Hz`
(30 characters) computes an integer of 10^8 digits, and `1,5 N` is 15 N. Here every number is a float,
every exponent a literal of at most MAX_EXPONENT, and pint is asked only for the unit each name stands for.

    quantity := term { ("*" | "·" | "/" | "per" | nothing) term }       left to right, as written
    term     := ["+" | "-"] factor [power]
              | ("square" | "sq" | "cubic") factor                       square metre, cubic mm
    factor   := number | unit | "(" quantity ")"
    power    := ("**" | "^") ["+" | "-"] number | superscript digits | "squared" | "cubed"
    number   := digits ["." digits] [("e" | "E") ["+" | "-"] digits], or "." digits [...]
    unit     := a name pint knows (letters, digits, "_", "µ"), "%" or "°"

A power's |exponent| is at most MAX_EXPONENT (quantities.py); the text is at most MAX_TEXT characters.
Anything else (a comma, a function call, a chained power `2**2**2`, an exponent in parentheses) is refused
with the reason: ExpressionError.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

#: superscript exponents as pint writes them ("m²", "s⁻¹")
_SUPERSCRIPT = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")
_TOKEN = re.compile(r"""
    (?P<space>\s+)
  | (?P<number>(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)
  | (?P<power>\*\*|\^)
  | (?P<superscript>⁻?[⁰¹²³⁴⁵⁶⁷⁸⁹]+)
  | (?P<op>[*·/()+-])
  | (?P<name>[^\W\d⁰¹²³⁴⁵⁶⁷⁸⁹][^\W⁰¹²³⁴⁵⁶⁷⁸⁹]*|%|°)   # superscript digits are \w, but a power
""", re.VERBOSE)
#: words pint reads as operators
_PREFIX_POWERS = {"square": 2, "sq": 2, "cubic": 3}
_SUFFIX_POWERS = {"squared": 2, "cubed": 3}
#: what float() would read as a number that is not finite
_NOT_FINITE = ("nan", "inf", "infinity")
#: symbols that name a unit
_SYMBOLS = {"%": "percent", "°": "degree"}


class ExpressionError(ValueError):
    """Text that is not a quantity this grammar reads; the message is the reason."""


@dataclass(frozen=True)
class _Token:
    kind: str  # number, power, superscript, op, name, end
    text: str
    at: int  # 0-based offset in the text


def tokens(text: str) -> list[_Token]:
    out, i = [], 0
    while i < len(text):
        m = _TOKEN.match(text, i)
        if m is None:
            what = "a comma (write 1.5, not 1,5; 1000, not 1,000)" if text[i] == "," else repr(text[i])
            raise ExpressionError(f"{what} at character {i + 1} is not part of a quantity")
        if m.lastgroup != "space":
            out.append(_Token(m.lastgroup or "", m.group(), i))
        i = m.end()
    out.append(_Token("end", "", len(text)))
    return out


def evaluate(text: str, max_exponent: float, unit: Callable[[str], Any], one: Callable[[float], Any]) -> Any:
    """The quantity `text` stands for: `one(x)` makes a dimensionless quantity of the float x, `unit(name)`
    the quantity 1 name (raising for a name it does not know). Every intermediate magnitude is a finite
    float; ExpressionError otherwise, or where the text does not follow the grammar."""
    return _Parser(tokens(text), max_exponent, unit, one).whole()


class _Parser:
    def __init__(self, toks: list[_Token], max_exponent: float, unit: Callable[[str], Any],
                 one: Callable[[float], Any]):
        self.toks, self.i = toks, 0
        self.max_exponent, self.unit, self.one = max_exponent, unit, one

    @property
    def tok(self) -> _Token:
        return self.toks[self.i]

    def take(self) -> _Token:
        tok = self.toks[self.i]
        self.i += 1
        return tok

    def unexpected(self) -> ExpressionError:
        tok = self.tok
        if tok.kind == "end":
            return ExpressionError("ends where a number or unit should follow")
        if tok.kind == "power":
            return ExpressionError(f"{tok.text!r} at character {tok.at + 1}: a power applies to a number, a unit "
                                   "or a parenthesis, once (write (m**2)**2, not m**2**2)")
        return ExpressionError(f"unexpected {tok.text!r} at character {tok.at + 1}")

    def whole(self) -> Any:
        if self.tok.kind == "end":
            raise ExpressionError("is empty")
        value = self.product()
        if self.tok.kind != "end":
            raise self.unexpected()
        return value

    def product(self) -> Any:
        value = self.term()
        while True:
            tok = self.tok
            if tok.kind == "op" and tok.text in "*·/":
                self.take()
                value = _checked(value, self.term(), "/" if tok.text == "/" else "*")
            elif tok.kind == "name" and tok.text == "per":
                self.take()
                value = _checked(value, self.term(), "/")
            elif tok.kind in ("number", "name") or (tok.kind == "op" and tok.text == "("):
                value = _checked(value, self.term(), "*")  # "kg m", "5 N": side by side is a product
            else:
                return value

    def term(self) -> Any:
        tok = self.tok
        if tok.kind == "op" and tok.text in "+-":
            self.take()
            value = self.term()
            return _checked(value, self.one(-1.0), "*") if tok.text == "-" else value
        if tok.kind == "name" and tok.text in _PREFIX_POWERS and self.toks[self.i + 1].kind == "name":
            self.take()
            return _checked(self.factor(), _PREFIX_POWERS[tok.text], "**")
        value = self.factor()
        tok = self.tok
        if tok.kind == "power":
            self.take()
            return _checked(value, self.exponent(), "**")
        if tok.kind == "superscript":
            self.take()
            return _checked(value, self.bounded(tok, float(tok.text.translate(_SUPERSCRIPT))), "**")
        if tok.kind == "name" and tok.text in _SUFFIX_POWERS:
            self.take()
            return _checked(value, _SUFFIX_POWERS[tok.text], "**")
        return value

    def exponent(self) -> float:
        sign = 1.0
        if self.tok.kind == "op" and self.tok.text in "+-":
            sign = -1.0 if self.take().text == "-" else 1.0
        tok = self.tok
        if tok.kind != "number":
            raise ExpressionError(f"an exponent is a plain number of at most {self.max_exponent:g}"
                                  + (f" (got {tok.text!r} at character {tok.at + 1})" if tok.kind != "end" else ""))
        self.take()
        return self.bounded(tok, sign * float(tok.text))

    def bounded(self, tok: _Token, x: float) -> float:
        if not abs(x) <= self.max_exponent:
            raise ExpressionError(f"exponent {x:g} at character {tok.at + 1} is beyond {self.max_exponent:g}: "
                                  f"a unit's power is at most {self.max_exponent:g}")
        return x

    def factor(self) -> Any:
        tok = self.take()
        if tok.kind == "number":
            return _finite(self.one(float(tok.text)), tok)
        if tok.kind == "name":
            if tok.text.lower() in _NOT_FINITE:
                raise ExpressionError(f"must be finite (got {tok.text!r})")
            try:
                return self.unit(_SYMBOLS.get(tok.text, tok.text))
            except Exception:  # pint raises its own errors (UndefinedUnitError, ...) for a name it lacks
                raise ExpressionError(f"unknown unit {tok.text!r}") from None
        if tok.kind == "op" and tok.text == "(":
            value = self.product()
            if self.tok.kind != "op" or self.tok.text != ")":
                raise ExpressionError(f"the parenthesis at character {tok.at + 1} is not closed")
            self.take()
            return value
        self.i -= 1
        raise self.unexpected()


def _checked(a: Any, b: Any, op: str) -> Any:
    """a op b, refused where the magnitude leaves the finite floats (or is not real: (-8)**0.5)."""
    try:
        if op == "*":
            value = a * b
        elif op == "/":
            value = a / b
        else:
            value = a**b
    except OverflowError:
        raise ExpressionError("must be finite: it is beyond a double's range (about 1.8e308)") from None
    except ZeroDivisionError:
        raise ExpressionError("divides by zero") from None
    except Exception as err:  # pint refuses some products (offset units such as degC)
        raise ExpressionError(" ".join(str(err).split()) or type(err).__name__) from None
    return _finite(value, None)


def _finite(value: Any, tok: _Token | None) -> Any:
    x = value.magnitude
    if isinstance(x, complex):
        raise ExpressionError("computes a complex number (a negative number to a fractional power)")
    if not isinstance(x, float) or not math.isfinite(x):
        raise ExpressionError(f"must be finite: {'the number ' + repr(tok.text) if tok is not None else 'it'} is "
                              "beyond a double's range (about 1.8e308)")
    return value
