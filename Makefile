# make test : every test (geometry, headless FreeCAD, FreeCAD's own runner, GUI under Xvfb)
# make demo : the headless demo job -> demo_out/
# make bench: the timed benchmarks (never part of the tests)
PY ?= /usr/bin/python3
export QTWEBENGINE_CHROMIUM_FLAGS ?= --no-sandbox

.PHONY: deps test demo bench
deps:
	@.ci/install-deps

test: deps
	$(PY) -m pytest tests -v -p no:cacheprovider

demo: deps
	$(PY) examples/demo.py demo_out

bench: deps
	$(PY) benchmarks/bench_stretch.py
	$(PY) benchmarks/bench_bend_twist.py
	$(PY) benchmarks/bench_dimension_drive.py
	$(PY) benchmarks/bench_area_constrain.py
	$(PY) benchmarks/bench_direct_push.py
