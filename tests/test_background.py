"""bem.common.background.BackgroundCall: the value of a call made in a daemon thread, or its error."""

import threading

import pytest

from bem.common.background import BackgroundCall


def test_the_call_runs_in_another_daemon_thread_and_returns_its_value():
    caller = threading.get_ident()
    call = BackgroundCall(lambda a, b: (a + b, threading.get_ident()), 2, 3, name="adder")
    assert call.daemon and call.name == "adder"
    value, ident = call.result()
    assert value == 5 and ident != caller
    assert call.result() == (5, ident)           # read again: the same value


def test_an_exception_is_raised_where_the_result_is_read():
    def fail():
        raise KeyError("inside")

    call = BackgroundCall(fail)
    with pytest.raises(KeyError, match="inside"):
        call.result()


def test_a_function_that_is_not_callable_is_refused():
    with pytest.raises(TypeError, match="function must be callable"):
        BackgroundCall(42)
