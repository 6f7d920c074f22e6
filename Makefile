# prism: two commands on a fresh Debian 12 machine (see README).
#   make render   installs what is missing, builds, renders the default scene to prism.png
#   make test     runs the whole test suite (both feature sets)
#   make lint     the module layering (no import cycles, no upward imports), rustfmt and clippy
#                 (-D warnings) on both feature sets; CI runs it before make test
#   make pgo      a profile-guided release build into target/pgo/release/prism (8-15 % faster renders,
#                 same images; installs llvm-N for rustc's LLVM N; two release builds)
#   make oidn     installs Intel Open Image Denoise 2 into target/oidn/lib for `prism render --denoise`
#                 (loaded at run time; make test installs it too, so its tests run; without it
#                 they skip, saying why)
#   make test-embree4  installs Embree 4 and runs the whole suite against it (not part of make test)
#   make test-slurm    a split render (--part i/N, checkpoints, requeue, merge) on a one-node Slurm
#                      cluster it starts and stops (root; installs munge and Slurm; not part of make test)
#   make compat   renders the pbrt-v4 compatibility scenes beside the repository, writes docs/compatibility.md

CARGO ?= cargo
SPP ?= 64

.PHONY: deps oidn pgo render test test-default test-pure test-embree4 test-slurm lint compat

deps:
	bash scripts/install-deps.sh

oidn:
	bash scripts/install-oidn.sh

pgo: deps
	bash scripts/build-pgo.sh

render: deps
	$(CARGO) build --release
	./target/release/prism render --spp $(SPP) --resolution 512x512 -o prism.png

test: deps oidn test-default test-pure

test-default:
	$(CARGO) test

# Without the C libraries only the backends (accel, image) and what picks them behave
# differently: the end-to-end suite runs again, on the pure-Rust backends (the pure-Rust paths'
# unit tests already ran in test-default, where both backends are built; what depends on the
# build is tested in the suite). Compiling the unit tests a second time would cost more than
# running them.
test-pure:
	$(CARGO) test --no-default-features --test suite

# The Embree 4 build (feature `embree4` instead of `embree`): every test, Embree's included.
test-embree4: deps
	bash scripts/install-embree4.sh
	$(CARGO) test --no-default-features --features embree4,oiio

# The README's Slurm recipe on a real (one-node, temporary) cluster: scripts/test-slurm.sh.
test-slurm: deps
	CARGO=$(CARGO) bash scripts/test-slurm.sh

compat:
	$(CARGO) build --release
	./target/release/prism compat --repeat 3 --doc docs/compatibility.md

lint: deps
	@command -v python3 >/dev/null || { echo "make lint: the layering check needs python3 (apt-get install python3)"; exit 1; }
	python3 scripts/layering.py src
	$(CARGO) fmt --check
	$(CARGO) clippy --all-targets -- -D warnings
	$(CARGO) clippy --all-targets --no-default-features -- -D warnings
