# mvtools: the project's entry points. `make demo` and `make test` are the README's two commands.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
BUILD ?= build

.DELETE_ON_ERROR:
.PHONY: install sample demo chain published test bench clean

install: $(VENV)/.installed

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

# Regenerate the committed sample data from the project's own synthetic scene.
sample: install
	$(BIN)/mvtools scene sample_data

# The demo on the sample scene: validate its configurations and cameras, synthesize camera 2
# of the line (1D mode) and of the arc (general mode) from its neighbours and score the result
# against the real view 2 (and, for contrast, the neighbouring view itself), write previews.
DEMO := $(BUILD)/demo
LINE := sample_data/line
ARC := sample_data/arc
VIEW := 256x192_yuv420p.yuv
demo: install
	mkdir -p $(DEMO)
	$(BIN)/mvtools inspect $(LINE)/synthesize_cam2.cfg $(LINE)/depth_cam2.cfg
	$(BIN)/mvtools inspect $(ARC)/cameras.txt
	$(BIN)/mvtools synthesize $(LINE)/synthesize_cam2.cfg -o $(DEMO)/line_v2_synthesized_$(VIEW)
	$(BIN)/mvtools synthesize $(ARC)/synthesize_cam2.cfg -o $(DEMO)/arc_v2_synthesized_$(VIEW)
	$(BIN)/mvtools evaluate $(LINE)/v2_texture_$(VIEW) $(DEMO)/line_v2_synthesized_$(VIEW)
	$(BIN)/mvtools evaluate $(ARC)/v2_texture_$(VIEW) $(DEMO)/arc_v2_synthesized_$(VIEW)
	$(BIN)/mvtools evaluate $(LINE)/v2_texture_$(VIEW) $(LINE)/v1_texture_$(VIEW)
	$(BIN)/mvtools convert $(DEMO)/line_v2_synthesized_$(VIEW) -o $(DEMO)/line_v2_synthesized_%02d.png
	$(BIN)/mvtools convert $(LINE)/v2_texture_256x192_yuv420p.yuv -o $(DEMO)/v2_texture_%02d.png
	$(BIN)/mvtools convert $(LINE)/v2_depth_256x192_yuv420p.yuv --depth --preview -o $(DEMO)/v2_depth_%02d.png
	$(BIN)/mvtools convert $(LINE)/v2_depth_256x192_gray16le.yuv --depth --to z --znear 2 --zfar 13 -o $(DEMO)/v2_z_%02d.pfm
	$(MAKE) --no-print-directory chain
	$(BIN)/mvtools report $(DEMO)
	@echo "demo outputs in $(DEMO), and the page of them all: $(DEMO)/report.html"

# The chain on the array as built (sample_data/distorted: lens distortion, turned cameras,
# colour mismatch): calibrate the array from its checkerboard captures, rectify it with
# the calibrated cameras (adding virtual cameras halfway between neighbours), correct its colours to camera 2,
# estimate the depth of every camera from its neighbours, leave out each inner camera in
# turn and synthesize it from its neighbours in 1D mode, score it against the real one,
# synthesize the virtual views between every pair of neighbours, and pack views and depth
# maps into one atlas. Every step is a file target: re-running redoes only what changed, and
# `make -j2 chain` runs independent views side by side.
CHAIN := $(DEMO)/chain
RECTIFIED := $(CHAIN)/rectified
CORRECTED := $(CHAIN)/corrected
DISTORTED := sample_data/distorted
CAMS := 0 1 2 3 4
texture = v$(1)_texture_$(VIEW)
BOARDS := $(wildcard $(DISTORTED)/checkerboard/cam*/capture*.png)

# the array calibrated from its own captures; the tangential terms, which its lenses do not
# have and the MPEG camera file cannot hold, are not fitted
$(CHAIN)/calibrated_cameras.txt: $(BOARDS) | install
	mkdir -p $(@D)
	$(BIN)/mvtools calibrate $(foreach c,$(CAMS),$(DISTORTED)/checkerboard/cam$(c)) --board 9x6 \
	    --square 0.05 --no-tangential -o $@ --report $(CHAIN)/calibration

$(foreach c,$(CAMS),$(RECTIFIED)/$(call texture,$(c))) $(RECTIFIED)/cameras.txt &: \
		$(CHAIN)/calibrated_cameras.txt $(foreach c,$(CAMS),$(DISTORTED)/$(call texture,$(c)))
	$(BIN)/mvtools rectify $(CHAIN)/calibrated_cameras.txt -o $(RECTIFIED) --virtual 1 \
	    $(foreach c,$(CAMS),--texture cam$(c) $(DISTORTED)/$(call texture,$(c)))

$(foreach c,$(CAMS),$(CORRECTED)/$(call texture,$(c)) $(CORRECTED)/cam$(c).lut.txt) &: \
		$(RECTIFIED)/cameras.txt $(foreach c,$(CAMS),$(RECTIFIED)/$(call texture,$(c)))
	$(BIN)/mvtools colorcorrect --reference cam2 --cameras $(RECTIFIED)/cameras.txt \
	    --depth-range 2 13 -o $(CORRECTED) \
	    $(foreach c,$(CAMS),--view cam$(c) $(RECTIFIED)/$(call texture,$(c)))

# the depth of camera N from cameras N-1 and N+1 (the end cameras from their one
# neighbour), with the sample line's DERS configuration
LAST := $(lastword $(CAMS))
$(CHAIN)/estimated_v%_depth_$(VIEW): $(foreach c,$(CAMS),$(CORRECTED)/$(call texture,$(c))) \
		$(LINE)/depth_cam2.cfg
	left=$$(($* - 1)); right=$$(($* + 1)); \
	if [ $* -eq 0 ]; then sides="MatchDirection=2 LeftCameraName= FileLeftViewImage="; \
	elif [ $* -eq $(LAST) ]; then sides="MatchDirection=1 RightCameraName= FileRightViewImage="; \
	else sides=""; fi; \
	$(BIN)/mvtools estimate-depth $(LINE)/depth_cam2.cfg FileCameraParameter=$(RECTIFIED)/cameras.txt \
	    LeftCameraName=cam$$left CenterCameraName=cam$* RightCameraName=cam$$right \
	    FileLeftViewImage=$(CORRECTED)/v$${left}_texture_$(VIEW) \
	    FileCenterViewImage=$(CORRECTED)/$(call texture,$*) \
	    FileRightViewImage=$(CORRECTED)/v$${right}_texture_$(VIEW) $$sides FileOutputDepthMapImage=$@

# camera N left out and synthesized from cameras N-1 and N+1 (1D mode), then scored
$(CHAIN)/synthesized_v%_$(VIEW): $(LINE)/synthesize_cam2.cfg \
		$(foreach c,$(CAMS),$(CHAIN)/estimated_v$(c)_depth_$(VIEW))
	left=$$(($* - 1)); right=$$(($* + 1)); \
	$(BIN)/mvtools synthesize $(LINE)/synthesize_cam2.cfg CameraParameterFile=$(RECTIFIED)/cameras.txt \
	    LeftCameraName=cam$$left VirtualCameraName=cam$* RightCameraName=cam$$right \
	    LeftViewImageName=$(CORRECTED)/v$${left}_texture_$(VIEW) \
	    RightViewImageName=$(CORRECTED)/v$${right}_texture_$(VIEW) \
	    LeftDepthMapName=$(CHAIN)/estimated_v$${left}_depth_$(VIEW) \
	    RightDepthMapName=$(CHAIN)/estimated_v$${right}_depth_$(VIEW) -o $@

# the synthesized views are results in their own right, not intermediates to delete
.PRECIOUS: $(CHAIN)/synthesized_v%_$(VIEW)
$(CHAIN)/synthesized_v%.scores: $(CHAIN)/synthesized_v%_$(VIEW)
	$(BIN)/mvtools evaluate $(CORRECTED)/$(call texture,$*) $< > $@

# the virtual view halfway between cameras $(1) and $(2) (rectify --virtual 1 names it)
define between
$(CHAIN)/virtual/cam$(1)_cam$(2)_1_$(VIEW): $(LINE)/synthesize_cam2.cfg \
		$(CHAIN)/estimated_v$(1)_depth_$(VIEW) $(CHAIN)/estimated_v$(2)_depth_$(VIEW)
	mkdir -p $$(@D)
	$(BIN)/mvtools synthesize $(LINE)/synthesize_cam2.cfg CameraParameterFile=$(RECTIFIED)/cameras.txt \
	    LeftCameraName=cam$(1) VirtualCameraName=cam$(1)_cam$(2)_1 RightCameraName=cam$(2) \
	    LeftViewImageName=$(CORRECTED)/$(call texture,$(1)) \
	    RightViewImageName=$(CORRECTED)/$(call texture,$(2)) \
	    LeftDepthMapName=$(CHAIN)/estimated_v$(1)_depth_$(VIEW) \
	    RightDepthMapName=$(CHAIN)/estimated_v$(2)_depth_$(VIEW) -o $$@
endef
PAIRS := 0-1 1-2 2-3 3-4
$(foreach pair,$(PAIRS),$(eval $(call between,$(firstword $(subst -, ,$(pair))),$(lastword $(subst -, ,$(pair))))))
VIRTUAL_VIEWS := $(foreach pair,$(PAIRS),$(CHAIN)/virtual/cam$(subst -,_cam,$(pair))_1_$(VIEW))

INNER := $(filter-out $(firstword $(CAMS)) $(LAST),$(CAMS))
$(CHAIN)/atlas.yuv: $(foreach c,$(CAMS),$(CORRECTED)/$(call texture,$(c)) \
		$(CHAIN)/estimated_v$(c)_depth_$(VIEW))
	$(BIN)/mvtools pack --layout atlas -o $@ \
	    $(foreach c,$(CAMS),--view cam$(c) $(CORRECTED)/$(call texture,$(c))) \
	    $(foreach c,$(CAMS),--depth cam$(c) $(CHAIN)/estimated_v$(c)_depth_$(VIEW))

chain: $(foreach c,$(INNER),$(CHAIN)/synthesized_v$(c).scores) \
		$(VIRTUAL_VIEWS) $(CHAIN)/atlas.yuv
	@echo "each inner camera left out and synthesized from its rectified, colour-corrected"
	@echo "neighbours and their estimated depth (Y-PSNR U V YUV Y-SSIM IV-PSNR, mean of the frames):"
	@for c in $(INNER); do printf 'cam%s ' $$c; grep '^  mean' $(CHAIN)/synthesized_v$$c.scores; done
	@echo "virtual views halfway between neighbours: $(notdir $(VIRTUAL_VIEWS))"
	$(BIN)/mvtools bitrate --size 1920x1080 --fps 25 --views 9

# Published material (../shared/data, or DATA=...): depth estimated for the two outer views
# of a Middlebury triple from that pair, the middle view synthesized from them (1D mode)
# and scored against the real one; and Kendo's camera 2 synthesized from cameras 1 and 3
# with the configuration shipped with the sequence (no real camera 2 is shipped to score).
DATA ?= ../shared/data
PUBLISHED := $(BUILD)/published
MIDDLEBURY := configs/middlebury

# $(1) case, $(2) its folder, $(3) left, middle, right picture names, $(4) disparities,
# $(5) focal * baseline of the outer pair, $(6) WxH
define middlebury_case
$(1)_left := $(word 1,$(3))
$(1)_middle := $(word 2,$(3))
$(1)_right := $(word 3,$(3))
$(1)_out := $(PUBLISHED)/$(1)
# depth values from the largest disparity searched to half a pixel (z = f B / d)
$(1)_znear := $$(shell awk 'BEGIN { print $(5) / $(4) }')
$(1)_zfar := $$(shell awk 'BEGIN { print $(5) * 2 }')

$$($(1)_out)/%_$(6)_yuv420p.yuv: $(2)/%.png | install
	mkdir -p $$(@D)
	$(BIN)/mvtools convert $$< -o $$@

$$($(1)_out)/$$($(1)_left).pfm: $(2)/$$($(1)_left).png $(2)/$$($(1)_right).png | install
	mkdir -p $$(@D)
	$(BIN)/mvtools estimate-depth --left $(2)/$$($(1)_left).png --right $(2)/$$($(1)_right).png \
	    --disparities $(4) -o $$@

$$($(1)_out)/$$($(1)_right).pfm: $(2)/$$($(1)_left).png $(2)/$$($(1)_right).png | install
	mkdir -p $$(@D)
	$(BIN)/mvtools estimate-depth --left $(2)/$$($(1)_left).png --right $(2)/$$($(1)_right).png \
	    --view right --disparities $(4) -o $$@

$$($(1)_out)/%_depth_$(6)_yuv420p.yuv: $$($(1)_out)/%.pfm
	$(BIN)/mvtools convert $$< --from disparity --focal 1 --baseline $(5) \
	    --znear $$($(1)_znear) --zfar $$($(1)_zfar) -o $$@

$$($(1)_out)/synthesized_$$($(1)_middle)_$(6)_yuv420p.yuv: \
		$$(foreach view,$$($(1)_left) $$($(1)_right),$$($(1)_out)/$$(view)_$(6)_yuv420p.yuv \
		$$($(1)_out)/$$(view)_depth_$(6)_yuv420p.yuv) $(MIDDLEBURY)/synthesize_middle.cfg
	$(BIN)/mvtools synthesize $(MIDDLEBURY)/synthesize_middle.cfg \
	    SourceWidth=$$(word 1,$$(subst x, ,$(6))) SourceHeight=$$(word 2,$$(subst x, ,$(6))) \
	    TotalNumberOfFrames=1 CameraParameterFile=$(MIDDLEBURY)/$(1)_cameras.txt \
	    LeftCameraName=$$($(1)_left) VirtualCameraName=$$($(1)_middle) RightCameraName=$$($(1)_right) \
	    LeftViewImageName=$$($(1)_out)/$$($(1)_left)_$(6)_yuv420p.yuv \
	    RightViewImageName=$$($(1)_out)/$$($(1)_right)_$(6)_yuv420p.yuv \
	    LeftDepthMapName=$$($(1)_out)/$$($(1)_left)_depth_$(6)_yuv420p.yuv \
	    RightDepthMapName=$$($(1)_out)/$$($(1)_right)_depth_$(6)_yuv420p.yuv \
	    $$(foreach side,Left Right,$$(side)NearestDepthValue=$$($(1)_znear) \
	    $$(side)FarthestDepthValue=$$($(1)_zfar)) -o $$@

$$($(1)_out)/$(1).scores: $$($(1)_out)/$$($(1)_middle)_$(6)_yuv420p.yuv \
		$$($(1)_out)/synthesized_$$($(1)_middle)_$(6)_yuv420p.yuv
	$(BIN)/mvtools evaluate $$^ > $$@
endef

$(eval $(call middlebury_case,cones,$(DATA)/middlebury/2003/cones,im2 im4 im6,64,4000,450x375))
$(eval $(call middlebury_case,tsukuba,$(DATA)/middlebury/2001/tsukuba,tsukuba2 tsukuba3 tsukuba4,32,2000,384x288))

KENDO := $(DATA)/mpeg/kendo
$(PUBLISHED)/kendo/synthesized_02_1024x768_yuv420p.yuv: $(KENDO)/config/VSRS/vsrs_kendo_ori.cfg | install
	mkdir -p $(@D)
	$(BIN)/mvtools synthesize $< --data-dir $(KENDO) -o $@

# every program run for these targets notes its time (the last run of each output counts)
published: export MVTOOLS_TIME_LOG := $(abspath $(PUBLISHED))/stage_times.tsv
published: $(PUBLISHED)/cones/cones.scores $(PUBLISHED)/tsukuba/tsukuba.scores \
		$(PUBLISHED)/kendo/synthesized_02_1024x768_yuv420p.yuv
	@echo "seconds per stage (program, output):"
	@awk -F '\t' '{ time[$$2 "\t" $$3] = $$1 } END { for (key in time) { split(key, part, "\t"); \
	    printf "%8.2f  %-24s %s\n", time[key], part[1], part[2] } }' $(MVTOOLS_TIME_LOG) | sort -k4
	@echo "published material: the middle view synthesized from the depth estimated for the outer pair"
	@for case in cones tsukuba; do printf '%-8s ' $$case; \
	    grep '^  mean' $(PUBLISHED)/$$case/$$case.scores; done
	@echo "(columns: Y-PSNR U-PSNR V-PSNR YUV-PSNR Y-SSIM IV-PSNR; the tests hold Cones im4 to 30.2 dB Y-PSNR on its 448x368 crop)"
	@echo "kendo: camera 2 synthesized from cameras 1 and 3: $(PUBLISHED)/kendo/synthesized_02_1024x768_yuv420p.yuv"

test: install
	$(BIN)/python -m pytest -q

bench: install
	$(BIN)/python benchmarks/run.py

clean:
	rm -rf $(BUILD)
