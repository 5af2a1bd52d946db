"""A value computed the first time it is read and kept on its object.

:func:`functools.cached_property` of Python 3.11 computes under one lock per *class*
attribute, shared by every instance: while one thread builds a slow value (the 6-DOF
table's model takes seconds), every other object of the class waits to read its own,
already quick, value.  :class:`once` locks per instance instead, so only readers of the
same object wait for it (and the value is still computed once)."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any, Generic, TypeVar, overload

T = TypeVar("T")

#: The attribute holding an object's lock for its :class:`once` values.
_LOCK = "_once_lock"


class _Lock:
    """An object's lock for its :class:`once` values; a copied or pickled object gets a
    lock of its own (a lock itself cannot be copied)."""

    def __init__(self) -> None:
        self._lock = threading.RLock()

    def __enter__(self) -> bool:
        return self._lock.acquire()

    def __exit__(self, *exc: object) -> None:
        self._lock.release()

    def __deepcopy__(self, memo: dict[int, Any]) -> _Lock:
        return _Lock()

    def __reduce__(self) -> tuple[type[_Lock], tuple[()]]:
        return (_Lock, ())


class once(Generic[T]):  # noqa: N801 - used as a decorator, like cached_property
    """``@once`` over a method: its value is computed at the first read and kept in the
    instance's ``__dict__`` (frozen dataclasses included, as with ``cached_property``)."""

    def __init__(self, fn: Callable[[Any], T]) -> None:
        self.fn = fn
        self.name = fn.__name__
        self.__doc__ = fn.__doc__

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    @overload
    def __get__(self, obj: None, owner: type | None = None) -> once[T]: ...

    @overload
    def __get__(self, obj: object, owner: type | None = None) -> T: ...

    def __get__(self, obj: object | None, owner: type | None = None) -> T | once[T]:
        if obj is None:
            return self
        values = obj.__dict__
        if self.name in values:
            return values[self.name]
        lock = values.setdefault(_LOCK, _Lock())  # atomic: one lock per object
        with lock:
            if self.name not in values:  # another reader may have computed it meanwhile
                values[self.name] = self.fn(obj)
            return values[self.name]
