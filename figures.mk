# Figures of the reference paper and validation against the measured data.
# Included from the Makefile (which defines BIN and STAMP); on its own: make -f Makefile -f figures.mk figures
#
#   make figures         every figure at full resolution        -> figures/out/figNN.png
#   make figures-quick   every figure from coarse copies of the specs (CI) -> figures/out/quick/figNN.png
#   make validate        measured phase lags against theory and simulation -> results/validation/
#
# A figure is rebuilt only when its script, figures/common.py or one of its cubes changed; cubes
# come from the Makefile's rule results/%.nc: configs/%.yaml. Scripts write their PNG under a
# temporary name and rename it into place; .DELETE_ON_ERROR covers everything else.

BIN   ?= .venv/bin
STAMP ?= .venv/.installed-stamp

.DELETE_ON_ERROR:
.PHONY: figures figures-quick validate

FIG_OUT := figures/out
NUM     := results/numerical

# The cubes each figure script reads, in the order it takes them (theory: configs/*.yaml;
# simulation: configs/numerical/*.yaml).
CUBES_fig01b := $(NUM)/fig01b_viscous_zeta005.nc $(NUM)/fig01b_viscous_zeta010.nc \
                $(NUM)/fig01b_viscous_zeta020.nc $(NUM)/fig01b_viscous_zeta050.nc
CUBES_fig04  := results/fig04_force_amplitude.nc
CUBES_fig05  := results/fig05_force_phase.nc
CUBES_fig07  := results/fig07_base_transmissibility.nc
CUBES_fig08  := results/fig08_transition_force_ratio.nc
CUBES_fig10  := results/fig10_joined_relative_amplitude.nc
CUBES_fig11  := results/fig11_joined_relative_phase.nc
CUBES_fig13  := results/fig13_joined_regime_map.nc
CUBES_fig14  := results/fig14a_joined_transmissibility.nc results/fig14b_joined_inversion.nc
CUBES_fig15  := results/fig11_joined_relative_phase.nc
CUBES_fig16  := results/fig11_joined_relative_phase.nc
CUBES_fig17  := $(NUM)/fig17_base_numerical.nc $(NUM)/fig17b_base_numerical_low_r.nc
CUBES_fig18  := $(NUM)/fig17_base_numerical.nc results/fig07_base_transmissibility.nc
CUBES_fig19  := $(NUM)/fig19_base_time_histories.nc
CUBES_fig20  := $(NUM)/fig20_joined_numerical.nc
CUBES_fig21  := $(NUM)/fig20_joined_numerical.nc results/fig21_joined_theory.nc
CUBES_fig22  := $(NUM)/fig22_joined_stick_slip_history.nc
# beyond the paper: stepped-sine sweeps up and down with static friction, over the two states
CUBES_hysteresis := $(NUM)/hysteresis_joined_up.nc $(NUM)/hysteresis_joined_down.nc \
                    $(NUM)/hysteresis_joined_starts.nc
# beyond the paper: the Jenkins contact (effect contact_stiffness) at several kappa, and the rigid contact
CUBES_jenkins := $(NUM)/jenkins_base_kappa1.nc $(NUM)/jenkins_base_kappa10.nc $(NUM)/jenkins_base_kappa100.nc \
                 $(NUM)/jenkins_base_kappa1000.nc $(NUM)/jenkins_base_rigid.nc
# beyond the paper: a blade with an under-platform damper, a structure of three masses (issue 31)
CUBES_blade_damper := results/blade_damper.nc

FIGURE_NAMES := fig01b fig04 fig05 fig07 fig08 fig10 fig11 fig13 fig14 fig15 fig16 \
                fig17 fig18 fig19 fig20 fig21 fig22 hysteresis jenkins blade_damper
FIGURES      := $(FIGURE_NAMES:%=$(FIG_OUT)/%.png)
QUICK_FIGURES := $(FIGURE_NAMES:%=$(FIG_OUT)/quick/%.png)

# quick cubes: results/quick/<same path below results/>
quick_cubes = $(patsubst results/%,results/quick/%,$(CUBES_$(1)))

define figure_rules
$(FIG_OUT)/$(1).png: figures/$(1).py figures/common.py $(CUBES_$(1)) $(STAMP)
	$(BIN)/python figures/$(1).py $(CUBES_$(1)) $$@
$(FIG_OUT)/quick/$(1).png: figures/$(1).py figures/common.py $(call quick_cubes,$(1)) $(STAMP)
	$(BIN)/python figures/$(1).py $(call quick_cubes,$(1)) $$@
endef
$(foreach f,$(FIGURE_NAMES),$(eval $(call figure_rules,$(f))))

figures: $(FIGURES)

figures-quick: $(QUICK_FIGURES)

# Coarse copies of the specs (at most 100 frequency ratios, 31 force ratios), kept between runs.
.PRECIOUS: results/quick/%.yaml
results/quick/%.yaml: configs/%.yaml figures/quick_spec.py $(STAMP)
	$(BIN)/python figures/quick_spec.py --num 100 --max-force-ratios 31 $< $@

# the structure's engine costs more a point than the 1-DoF kernels: its quick copy is coarser (40 x 11)
results/quick/blade_damper.yaml: configs/blade_damper.yaml figures/quick_spec.py $(STAMP)
	$(BIN)/python figures/quick_spec.py --num 40 --max-force-ratios 11 $< $@

results/quick/%.nc: results/quick/%.yaml $(STAMP)
	$(BIN)/fsweep run $< -o $@ --overwrite --quiet

# VALIDATION_DATA=path overrides the default data file, <repo>/../shared/data/experiment_phase_fixed_wall.csv
VALIDATION_DATA ?=
validate: $(STAMP)
	$(BIN)/python -m friction_sweep.validation --overwrite --output-dir results/validation $(if $(VALIDATION_DATA),--data $(VALIDATION_DATA))
