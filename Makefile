# geoblock build.  `make` builds the optimized program, `make debug` the checked
# one, `make run` / `make test` / `make bench` install what is missing, build
# and run.  Module dependencies are generated from the sources (tools/fdeps.sh).

VERSION := 0.2.0
BUILD ?= opt
FC := mpif90
NP ?= 2
MPIRUN ?= mpirun --oversubscribe
export OMPI_ALLOW_RUN_AS_ROOT := 1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM := 1
export OMPI_MCA_rmaps_base_oversubscribe := 1

HDF5_INC := /usr/include/hdf5/openmpi
HDF5_LIB := /usr/lib/x86_64-linux-gnu/hdf5/openmpi

WARN := -std=f2008 -fimplicit-none -Wall -Wextra -Wno-unused-dummy-argument -Wno-compare-reals
ifeq ($(BUILD),debug)
  FFLAGS := -O0 -g $(WARN) -fcheck=all -fbacktrace -ffpe-trap=invalid,zero,overflow -finit-real=snan
  COPT := -O0 -g
  EXE_SUFFIX := -debug
else
  # -O3: the CSR product (csr_matrix%apply's loop, tools/spmv.f90 on Mandel's
  # pattern at the seed's size) 8.4 -> 7.4 ms; whole runs 0.925x the wall
  # time (Mandel 80x80x8, 1 rank) and 0.974x (contact n = 40, slip, 2 ranks),
  # farm-bench medians of 7 and 3, with the residual histories bit for bit
  # those of -O2 (no reassociation without -ffast-math; x86-64-v2 has no FMA)
  FFLAGS := -O3 -g -march=x86-64-v2 $(WARN)
  COPT := -O3 -g -march=x86-64-v2
  EXE_SUFFIX :=
endif

BDIR := build/$(BUILD)
ODIR := $(BDIR)/obj
MDIR := $(BDIR)/mod
INC := -I$(HDF5_INC) -I/usr/include -J$(MDIR) -I$(MDIR)
# the few C files (modules/bindings: what hypre reaches only through its
# internal header) are compiled with the MPI C compiler
CC := mpicc
CFLAGS := $(COPT) -std=gnu11 -Wall -Wextra -Wno-unused-parameter -I/usr/include/hypre
LIBS := -L$(HDF5_LIB) -lhdf5_fortran -lhdf5 -lHYPRE -ldmumps -lmumps_common -lpord \
        -lscalapack-openmpi -lmetis -llapack -lblas

# Sources are found in the tree (modules/<layer>, src/<layer>, tests/...):
# no hand-kept file list. File names are unique across the tree.
MAIN_SRC := src/drivers/geoblock.f90
LIB_SRC := $(sort $(filter-out $(MAIN_SRC),$(shell find modules src -name '*.f90')))
LIB_C_SRC := $(sort $(shell find modules src -name '*.c'))
TEST_COMMON := $(sort $(shell find tests/common -name '*.f90'))
TEST_SRC := $(sort $(shell find tests -name 'test_*.f90'))
ALL_SRC := $(LIB_SRC) $(TEST_COMMON) $(TEST_SRC) $(MAIN_SRC)

obj = $(addprefix $(ODIR)/,$(notdir $(1:.f90=.o)))
LIB_OBJ := $(call obj,$(LIB_SRC)) $(addprefix $(ODIR)/,$(notdir $(LIB_C_SRC:.c=.o)))
TEST_COMMON_OBJ := $(call obj,$(TEST_COMMON))
TEST_BIN := $(addprefix bin/tests/,$(notdir $(TEST_SRC:.f90=$(EXE_SUFFIX))))
LIBGB := $(BDIR)/libgeoblock.a
EXE := bin/geoblock$(EXE_SUFFIX)

vpath %.f90 $(sort $(dir $(ALL_SRC)))
vpath %.c $(sort $(dir $(LIB_C_SRC)))

.PHONY: all debug tests run test bench bench-large deps clean help reference images
.DEFAULT_GOAL := all

all: $(EXE)

debug:
	$(MAKE) BUILD=debug all tests

tests: $(TEST_BIN)

$(EXE): $(call obj,$(MAIN_SRC)) $(ODIR)/build_info.o $(LIBGB) | bin
	$(FC) $(FFLAGS) -o $@ $^ $(LIBS)

# version, git commit and library versions for `geoblock --version`
# (regenerated at every make, rewritten only when it changes)
BUILD_INFO := $(BDIR)/gen/build_info.f90
$(BUILD_INFO): FORCE
	@bash tools/build_info.sh $@
FORCE:
$(ODIR)/build_info.o: $(BUILD_INFO) | $(ODIR) $(MDIR)
	$(FC) $(FFLAGS) $(INC) -c $< -o $@
$(call obj,$(MAIN_SRC)): $(ODIR)/build_info.o

bin/tests/%$(EXE_SUFFIX): $(ODIR)/%.o $(TEST_COMMON_OBJ) $(LIBGB) | bin/tests
	$(FC) $(FFLAGS) -o $@ $^ $(LIBS)

$(LIBGB): $(LIB_OBJ)
	ar rcs $@ $^

$(ODIR)/%.o: %.f90 | $(ODIR) $(MDIR)
	$(FC) $(FFLAGS) $(INC) -c $< -o $@

$(ODIR)/%.o: %.c | $(ODIR)
	$(CC) $(CFLAGS) -c $< -o $@

$(BDIR)/deps.mk: $(ALL_SRC) tools/fdeps.sh | $(ODIR)
	@bash tools/fdeps.sh $(ODIR) $(ALL_SRC) > $@

-include $(BDIR)/deps.mk

$(ODIR) $(MDIR) bin bin/tests:
	@mkdir -p $@

deps:
	@bash tools/install_deps.sh

# The default deck (a small Mandel problem) on 2 ranks, then its plots.
DECK ?= input/mandel.nml
PYTHON ?= /usr/bin/python3
run: deps
	$(MAKE) all
	$(MPIRUN) -np $(NP) $(EXE) $(DECK)
	@if [ "$(DECK)" = input/mandel.nml ]; then \
	  $(PYTHON) postproc/plot_mandel.py out mandel out/mandel_pressure.png > /dev/null && \
	  $(PYTHON) postproc/plot_convergence.py out mandel out/mandel_convergence.png > /dev/null && \
	  echo "plots: out/mandel_pressure.png (pressure against the analytical solution)," \
	       "out/mandel_convergence.png (FGMRES residual histories)"; fi

test: deps
	$(MAKE) all tests
	@bash tests/run_tests.sh

# Benchmarks, in two tiers that each fit in a few hours here (bench/run_all.sh
# times each script and writes one report: machine, date, commit, tables).
# make bench (build/bench/REPORT.md): elasticity, Mandel with every block
# preconditioner variant, the peers (PETSc, hypre MGR, MUMPS) on the same
# systems, strong scaling, contact with the four contact preconditioners a
# user runs on 5 levels, our aFSAI against hypre's FSAI.
# make bench-large (build/bench/REPORT_large.md): the contact
# preconditioners' diagnostics, the fluid in the fractures, the Treporti and
# Reservoir stand-ins, HI24L up to the seed's size (16 GB of memory).
bench: deps
	$(MAKE) all
	@bash bench/run_all.sh standard

bench-large: deps
	$(MAKE) all
	@bash bench/run_all.sh large

# The deck reference, written by the binary from the parameter registry
# (doc/reference/decks.md; make test fails when the committed one differs).
reference: all
	@mkdir -p doc/reference
	OMPI_MCA_rmaps_base_oversubscribe=1 $(EXE) --reference > doc/reference/decks.md
	@echo "wrote doc/reference/decks.md"

# The manual's pictures (doc/images/), from small runs of the tutorials' decks.
images: all
	@bash postproc/make_images.sh

clean:
	rm -rf build bin

help:
	@echo "make [all|debug|run|test|bench|bench-large|reference|images|clean]  (BUILD=opt|debug, NP=ranks, DECK=deck)"
