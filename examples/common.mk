# examples/common.mk: what every example Makefile shares (issue 28). An example's Makefile starts
#
#   PDGRAIN ?= $(abspath $(dir $(firstword $(MAKEFILE_LIST)))../..)
#   include $(or $(wildcard $(PDGRAIN)/examples/common.mk),$(error PDGRAIN=... holds no ...))
#
# so it runs where it is and from a copy: `make quick PDGRAIN=/path/to/pdgrain` in a copied
# folder (PDGRAIN: the pdgrain source tree, or any folder holding its examples/common.mk and
# workflows/analysis/). Variables (each can be given on the command line):
#   PDGRAIN   the pdgrain tree (default: two levels above the Makefile)
#   BIN       the tools (default $(PDGRAIN)/build/bin, or $(PDGRAIN)/bin when that holds pd-solve)
#   PY        Python with numpy, h5py, scipy, matplotlib (default /usr/bin/python3)
#   OUT       the outputs (default out/)
#   SOLVE     the solver command (default $(BIN)/pd-solve; RANKS=N: under mpirun, N ranks)
BIN ?= $(if $(wildcard $(PDGRAIN)/bin/pd-solve),$(PDGRAIN)/bin,$(PDGRAIN)/build/bin)
PY ?= /usr/bin/python3
OUT ?= out
ANALYSIS ?= $(PDGRAIN)/workflows/analysis
RANKS ?= 1
# Open MPI refuses root without these; --oversubscribe: more ranks than cores.
MPIRUN ?= env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe
SOLVE ?= $(if $(filter 1,$(RANKS)),$(BIN)/pd-solve,$(MPIRUN) -np $(RANKS) $(BIN)/pd-solve)
# Outputs are remade when a scene or a tool changes (a rebuilt pdgrain reruns the checks).
TOOLS = $(BIN)/pd-pack $(BIN)/pd-solve

# The checkers of workflows/analysis (README.md there): the energy balance and restitution of a
# run (check_impact.py) and the physics bounds of every frame (check_run.py: no interpenetration,
# nothing through a wall, energy bounds, speed bound).
CHECK_IMPACT = $(PY) $(ANALYSIS)/check_impact.py
CHECK_RUN = $(PY) $(ANALYSIS)/check_run.py

# $(eval $(call pd_solved,FILE.h5,SCENE,PACK_ARGS,SOLVE_ARGS)): FILE.h5 packed from SCENE and
# solved (pd-solve's errors fail the target, exit 3 of a guard included); the file appears only
# once the solve succeeded (a failed run stays in FILE.h5.packed until the next make redoes it).
define pd_solved
$(1): $(2) $$(TOOLS)
	@mkdir -p $$(dir $$@)
	$$(BIN)/pd-pack $$< -o $$@.packed -q --overwrite $(3)
	$$(SOLVE) $$@.packed -q $(4)
	mv $$@.packed $$@
endef

# $(call pd_plots,FILE.h5,PREFIX): energies and damage maps (frames PLOT_FRAMES) of a run, in
# OUT/PREFIXenergies.png and OUT/PREFIXdamage_maps.png.
PLOT_FRAMES ?= 0,200,-1
pd_plots = $(PY) $(ANALYSIS)/plot_energies.py $(1) -o $(OUT)/$(2)energies.png && \
  $(PY) $(ANALYSIS)/plot_damage_maps.py $(1) --frames $(PLOT_FRAMES) -o $(OUT)/$(2)damage_maps.png

# Every example's default goal is its `all`; `clean` is shared.
.DEFAULT_GOAL := all
.PHONY: clean
clean:
	rm -rf $(OUT)
