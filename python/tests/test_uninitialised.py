"""No object made by Class.__new__(Class) without __init__ crashes the interpreter when used:
every method and property of every class raises instead. pybind11 would otherwise hand such an
object uninitialised memory. It runs in a child interpreter, so that a crash is a failure of
this test and not the end of the suite."""

import os
import subprocess
import sys
import textwrap

PROBE = textwrap.dedent("""
    import inspect, pickle
    import inertia
    from inertia import _inertia

    classes = [c for n, c in vars(_inertia).items()
               if isinstance(c, type) and not issubclass(c, BaseException)]
    assert len(classes) > 30, len(classes)
    raised = calls = 0
    for cls in classes:
        for name in dir(cls):
            if name in ("__new__", "__init__", "__init_subclass__", "__class__", "__subclasshook__",
                        "__setstate__", "__del__", "__delattr__", "__setattr__", "__dir__",
                        "__getattribute__", "__reduce__", "__reduce_ex__", "__sizeof__",
                        "__format__", "__str__", "__doc__", "__module__", "__dict__",
                        "__weakref__"):
                continue
            blank = cls.__new__(cls)
            try:
                member = getattr(blank, name)  # properties run here
            except TypeError:
                raised += 1
                continue
            if not callable(member) or inspect.isclass(member):
                continue
            for args in ((), (blank,), (0,), (0, 0), (blank, blank, blank)):
                calls += 1
                try:
                    member(*args)
                except Exception:
                    raised += 1
    # Pickling a blank one raises too (its __getstate__ reads it).
    for cls in classes:
        try:
            pickle.dumps(cls.__new__(cls))
        except Exception:
            pass
    blank = inertia.World.__new__(inertia.World)
    try:
        blank.step()
    except TypeError as e:
        assert "never initialised" in str(e), e
    else:
        raise AssertionError("step on a blank World did not raise")
    # A world made properly still works beside them.
    w = inertia.World()
    w.step()
    print("survived", len(classes), calls, raised)
""")


def test_blank_instances_raise_instead_of_crashing():
    result = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True,
                            env=os.environ, timeout=120)
    assert result.returncode == 0, (result.returncode, result.stderr[-2000:])
    assert result.stdout.startswith("survived"), result.stdout
