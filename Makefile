# make test : every test (geometry, headless FreeCAD, FreeCAD's own runner, GUI under Xvfb)
# make demo : the headless demo job -> demo_out/
# make bench: the timed benchmarks (never part of the tests)
# make realparts: the real-parts matrix (issue 10) as a table
# make reliability: the reliability campaign (issue 11), 60 cases per feature, as a table
# make test-freecad11: make test again inside a Debian sid chroot with FreeCAD 1.1 (Qt6,
#   Python 3.14); root; the chroot is built once in /var/cache/freecad_deform/sid (.ci/chroot-test)
PY ?= /usr/bin/python3
export QTWEBENGINE_CHROMIUM_FLAGS ?= --no-sandbox

.PHONY: deps test demo bench test-freecad11 realparts reliability
deps:
	@.ci/install-deps

test: deps
	$(PY) -m pytest deform_tests -v -p no:cacheprovider

# GUI screenshots of this run go to deform_tests/gui/_out/freecad-1.1/
test-freecad11:
	.ci/chroot-test sid env DEFORM_GUI_OUT=$(CURDIR)/deform_tests/gui/_out/freecad-1.1 make test

demo: deps
	$(PY) examples/demo.py demo_out

bench: deps
	$(PY) benchmarks/bench_stretch.py
	$(PY) benchmarks/bench_bend_twist.py
	$(PY) benchmarks/bench_dimension_drive.py
	$(PY) benchmarks/bench_area_constrain.py
	$(PY) benchmarks/bench_direct_push.py
	$(PY) benchmarks/bench_flex.py
	$(PY) benchmarks/mesh_samples.py
	$(PY) benchmarks/bench_clouds_meshes.py
	$(PY) benchmarks/bench_dimension_drive_fem.py

# the real-parts matrix (issue 10) as a table: case, result, oracle error, seconds, OCCT floor
realparts: deps
	$(PY) -m deform_tests.realparts.matrix

# the reliability campaign (issue 11): each case in its own process, classified; a table
reliability: deps
	$(PY) -m deform_tests.reliability.campaign --per-feature 60
