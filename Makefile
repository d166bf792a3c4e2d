# mvtools: the project's entry points. `make demo` and `make test` are the README's two commands.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
BUILD ?= build

.DELETE_ON_ERROR:
.PHONY: install sample demo chain navigation pipeline published test test-fast lint bench clean

install: $(VENV)/.installed

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet -e '.[test]'
	# byte-compiled once, as an installed package is, so no run compiles the sources
	$(BIN)/python -m compileall -q mvtools
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
	$(BIN)/mvtools convert $(LINE)/v2_depth_256x192_gray16le.yuv --depth --to z --depth-range 2 13 -o $(DEMO)/v2_z_%02d.pfm
	$(MAKE) --no-print-directory chain navigation
	$(BIN)/mvtools report $(DEMO)
	@echo "demo outputs in $(DEMO), and the page of them all: $(DEMO)/report.html"

# The chain on the array as built (sample_data/distorted: lens distortion, turned cameras,
# colour mismatch): calibrate the array from its checkerboard captures, rectify it with
# the calibrated cameras (adding virtual cameras halfway between neighbours), correct its
# colours to camera 2, estimate the depth of every camera from its neighbours, leave out
# each inner camera in turn and synthesize it from its neighbours in 1D mode, score it
# against the real one, synthesize the virtual views between every pair of neighbours, and
# pack views and depth maps into one atlas. Every step is a file target: re-running redoes
# only what changed, and `make -j2 chain` runs independent views and frame chunks side by side.
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

# the scene's true depth maps are rectified with the views: the truth the estimates are scored against
true_depth = v$(1)_depth_256x192_gray16le.yuv
$(foreach c,$(CAMS),$(RECTIFIED)/$(call texture,$(c)) $(RECTIFIED)/$(call true_depth,$(c))) \
		$(RECTIFIED)/cameras.txt &: $(CHAIN)/calibrated_cameras.txt \
		$(foreach c,$(CAMS),$(DISTORTED)/$(call texture,$(c)) $(DISTORTED)/$(call true_depth,$(c)))
	$(BIN)/mvtools rectify $(CHAIN)/calibrated_cameras.txt -o $(RECTIFIED) --virtual 1 \
	    $(foreach c,$(CAMS),--view cam$(c) $(DISTORTED)/$(call texture,$(c))) \
	    $(foreach c,$(CAMS),--depth cam$(c) $(DISTORTED)/$(call true_depth,$(c))) --depth-range 2 13

$(foreach c,$(CAMS),$(CORRECTED)/$(call texture,$(c)) $(CORRECTED)/cam$(c).lut.txt) &: \
		$(RECTIFIED)/cameras.txt $(foreach c,$(CAMS),$(RECTIFIED)/$(call texture,$(c)))
	$(BIN)/mvtools colorcorrect --reference cam2 --cameras $(RECTIFIED)/cameras.txt \
	    --depth-range 2 13 -o $(CORRECTED) \
	    $(foreach c,$(CAMS),--view cam$(c) $(RECTIFIED)/$(call texture,$(c)))

# Frame chunks: estimate-depth and synthesize, the costly stages, run per view in chunks of
# CHUNK frames (0: whole videos), each chunk a target of its own under $(CHUNKS) (outside
# the demo's folder, which the report shows), so that `make -j N` runs chunks side by side;
# the chunks are concatenated into the view's video, the bytes of one run over all frames
# (tests/test_chunks.py, and $(CHUNKS)/checked below).
CHUNK ?= 2
CHUNKS := $(BUILD)/chunks
# the sample videos' length: bytes over the bytes of a 256x192 4:2:0 frame
FRAMES := $(shell echo $$(( $$(stat -c %s $(LINE)/$(call texture,0)) / (256 * 192 * 3 / 2) )))
CHUNK_STARTS := $(if $(filter-out 0,$(CHUNK)),$(shell seq 0 $(CHUNK) $$(($(FRAMES) - 1))))
# frames in the chunk from frame $(1): CHUNK, or what is left at the end
chunk_frames = $(shell left=$$(($(FRAMES) - $(1))); echo $$((left < $(CHUNK) ? left : $(CHUNK))))

# $(1) a video made frame by frame, $(2) its prerequisites, $(3) the make function that
# gives the command writing it from its arguments: $(4), an output name and frame-range
# options. A chunk's JSON sidecar (estimate-depth's Znear/Zfar) serves the whole video.
define chunked
ifeq ($(CHUNK_STARTS),)
$(1): $(2)
	mkdir -p $$(@D)
	$$(call $(3),$(4),$$@,)
else
$(foreach start,$(CHUNK_STARTS),$(CHUNKS)/from$(start)_$(notdir $(1))): $(CHUNKS)/from%_$(notdir $(1)): $(2)
	mkdir -p $$(@D)
	$$(call $(3),$(4),$$@,--start-frame $$* --frames $$(call chunk_frames,$$*))
$(1): $(foreach start,$(CHUNK_STARTS),$(CHUNKS)/from$(start)_$(notdir $(1)))
	mkdir -p $$(@D)
	cat $$^ > $$@
	if [ -e $$<.json ]; then cp $$<.json $$@.json; fi
endif
endef

# neighbours along the line: left_of_N and right_of_N (none at the ends)
PAIRS := 0-1 1-2 2-3 3-4
pair_left = $(firstword $(subst -, ,$(1)))
pair_right = $(lastword $(subst -, ,$(1)))
$(foreach pair,$(PAIRS),$(eval right_of_$(call pair_left,$(pair)) := $(call pair_right,$(pair))) \
    $(eval left_of_$(call pair_right,$(pair)) := $(call pair_left,$(pair))))

# the depth of camera $(1) into $(2) from its neighbours (an end camera from its one
# neighbour), with the sample line's DERS configuration; $(3) frame-range options
depth_side = $(if $(3),$(2)CameraName=cam$(3) File$(2)ViewImage=$(CORRECTED)/$(call texture,$(3)),$\
    MatchDirection=$(1) $(2)CameraName= File$(2)ViewImage=)
estimate_depth = $(BIN)/mvtools estimate-depth $(LINE)/depth_cam2.cfg $\
    FileCameraParameter=$(RECTIFIED)/cameras.txt CenterCameraName=cam$(1) $\
    FileCenterViewImage=$(CORRECTED)/$(call texture,$(1)) $\
    $(call depth_side,2,Left,$(left_of_$(1))) $(call depth_side,1,Right,$(right_of_$(1))) $\
    FileOutputDepthMapImage=$(2) $(3)
depth = $(CHAIN)/estimated_v$(1)_depth_$(VIEW)
CORRECTED_VIEWS := $(foreach c,$(CAMS),$(CORRECTED)/$(call texture,$(c)))
$(foreach c,$(CAMS),$(eval $(call chunked,$(call depth,$(c)),$\
    $(foreach v,$(left_of_$(c)) $(c) $(right_of_$(c)),$(CORRECTED)/$(call texture,$(v))) $\
    $(LINE)/depth_cam2.cfg,estimate_depth,$(c))))

# the view named $(word 2,$(1)) synthesized into $(2) from cameras $(word 1,$(1)) and
# $(word 3,$(1)) (1D mode); $(3) frame-range options
synthesize_view = $(BIN)/mvtools synthesize $(LINE)/synthesize_cam2.cfg $\
    CameraParameterFile=$(RECTIFIED)/cameras.txt LeftCameraName=cam$(word 1,$(1)) $\
    VirtualCameraName=$(word 2,$(1)) RightCameraName=cam$(word 3,$(1)) $\
    LeftViewImageName=$(CORRECTED)/$(call texture,$(word 1,$(1))) $\
    RightViewImageName=$(CORRECTED)/$(call texture,$(word 3,$(1))) $\
    LeftDepthMapName=$(call depth,$(word 1,$(1))) RightDepthMapName=$(call depth,$(word 3,$(1))) $\
    -o $(2) $(3)
synthesis_inputs = $(LINE)/synthesize_cam2.cfg $(call depth,$(word 1,$(1))) $(call depth,$(word 3,$(1)))

# each inner camera left out and synthesized from its neighbours, then scored
INNER := $(filter-out $(firstword $(CAMS)) $(lastword $(CAMS)),$(CAMS))
left_out = $(left_of_$(1)) cam$(1) $(right_of_$(1))
$(foreach c,$(INNER),$(eval $(call chunked,$(CHAIN)/synthesized_v$(c)_$(VIEW),$\
    $(call synthesis_inputs,$(call left_out,$(c))),synthesize_view,$(call left_out,$(c)))))
$(CHAIN)/synthesized_v%.scores: $(CHAIN)/synthesized_v%_$(VIEW)
	$(BIN)/mvtools evaluate $(CORRECTED)/$(call texture,$*) $< > $@

# the estimated depth of each camera against the truth, as disparities towards a neighbour
$(CHAIN)/estimated_v%_depth.errors.json: $(call depth,%) $(RECTIFIED)/$(call true_depth,%)
	$(BIN)/mvtools evaluate --depth $(RECTIFIED)/$(call true_depth,$*) $< --reference-depth-range 2 13 \
	    --cameras $(RECTIFIED)/cameras.txt --camera cam$* \
	    --neighbour cam$(or $(right_of_$*),$(left_of_$*)) --json-file $@ > $(@:.json=.txt)
DEPTH_ERRORS := $(foreach c,$(CAMS),$(CHAIN)/estimated_v$(c)_depth.errors.json)

# the virtual view halfway between the cameras of each pair (rectify --virtual 1 names it)
between = $(call pair_left,$(1)) cam$(subst -,_cam,$(1))_1 $(call pair_right,$(1))
virtual_view = $(CHAIN)/virtual/cam$(subst -,_cam,$(1))_1_$(VIEW)
$(foreach pair,$(PAIRS),$(eval $(call chunked,$(call virtual_view,$(pair)),$\
    $(call synthesis_inputs,$(call between,$(pair))),synthesize_view,$(call between,$(pair)))))
VIRTUAL_VIEWS := $(foreach pair,$(PAIRS),$(call virtual_view,$(pair)))

# the chunks concatenated against one run over all frames, for the depth and the synthesis
# of camera 2 (nothing to check when CHUNK is 0)
CHECKED := 2
WHOLE := $(CHUNKS)/whole
$(CHUNKS)/checked: $(call depth,$(CHECKED)) $(CHAIN)/synthesized_v$(CHECKED)_$(VIEW)
	mkdir -p $(WHOLE)
	$(call estimate_depth,$(CHECKED),$(WHOLE)/$(notdir $(call depth,$(CHECKED))),) -q
	$(call synthesize_view,$(call left_out,$(CHECKED)),$(WHOLE)/synthesized_v$(CHECKED)_$(VIEW),) -q
	cmp $(call depth,$(CHECKED)) $(WHOLE)/$(notdir $(call depth,$(CHECKED)))
	cmp $(CHAIN)/synthesized_v$(CHECKED)_$(VIEW) $(WHOLE)/synthesized_v$(CHECKED)_$(VIEW)
	echo "chunks of $(CHUNK) frames (starting at $(CHUNK_STARTS)) concatenate to the bytes of one run" > $@


$(CHAIN)/atlas.yuv: $(CORRECTED_VIEWS) $(foreach c,$(CAMS),$(call depth,$(c)))
	$(BIN)/mvtools pack --layout atlas -o $@ \
	    $(foreach c,$(CAMS),--view cam$(c) $(CORRECTED)/$(call texture,$(c))) \
	    $(foreach c,$(CAMS),--depth cam$(c) $(call depth,$(c)))

# The sample line's depth and synthesis as Dask tasks (`mvtools run`, docs/pipeline.md): the
# same work as the depth and left-out-view targets above, on the sample line as rendered,
# with a local cluster of one worker per core.
pipeline: install
	$(BIN)/mvtools run configs/sample_line_pipeline.toml -o $(BUILD)/pipeline

# Free navigation on the line: a camera path through its five cameras, half an interval
# beyond the outer ones, rendered from all five views (static content), scored frame by frame
# against the scene ray-cast at each pose (the exact truth), and the two eyes of the same
# path side by side, as a headset takes them.
NAVIGATION := $(DEMO)/navigation
PATH_FRAMES := 16
NAVIGATE := $(BIN)/mvtools navigate $(LINE)/cameras.txt --depth-range 2 13 --static --precision 4 \
    --frames $(PATH_FRAMES) --extend 0.5 $(foreach c,$(CAMS),--view cam$(c) $(LINE)/$(call texture,$(c)) \
    --depth cam$(c) $(LINE)/v$(c)_depth_$(VIEW))
$(NAVIGATION)/path_$(VIEW) $(NAVIGATION)/path.csv &: $(foreach c,$(CAMS),$(LINE)/$(call texture,$(c))) | install
	mkdir -p $(@D)
	$(NAVIGATE) --poses-output $(NAVIGATION)/path.csv -o $(NAVIGATION)/path_$(VIEW)
$(NAVIGATION)/truth/path_texture_$(VIEW): $(NAVIGATION)/path.csv
	mkdir -p $(@D)
	$(BIN)/mvtools scene $(@D) --path $< --still
$(NAVIGATION)/path.scores: $(NAVIGATION)/truth/path_texture_$(VIEW) $(NAVIGATION)/path_$(VIEW)
	$(BIN)/mvtools evaluate $^ > $@
$(NAVIGATION)/stereo_512x192_yuv420p.yuv: $(foreach c,$(CAMS),$(LINE)/$(call texture,$(c))) | install
	mkdir -p $(@D)
	$(NAVIGATE) --stereo --layout side-by-side -o $@
navigation: $(NAVIGATION)/path.scores $(NAVIGATION)/stereo_512x192_yuv420p.yuv
	@echo "a path of $(PATH_FRAMES) frames through the line and beyond, against the scene at each pose"
	@echo "(Y-PSNR U V YUV Y-SSIM IV-PSNR, mean of the frames):"
	@grep '^  mean' $(NAVIGATION)/path.scores

# rate-distortion of the views and depth maps coded one by one and packed in one atlas, when
# Debian's x265 and ffmpeg are installed (mvtools encode runs them)
HAVE_ENCODERS := $(and $(shell command -v x265),$(shell command -v ffmpeg))
$(CHAIN)/compression/report.json: $(CORRECTED_VIEWS) $(foreach c,$(CAMS),$(call depth,$(c)))
	mkdir -p $(@D)
	$(BIN)/mvtools encode -o $(@D) --qp 22 --qp 27 --qp 32 --qp 37 --preset fast \
	    $(foreach c,$(CAMS),--view cam$(c) $(CORRECTED)/$(call texture,$(c))) \
	    $(foreach c,$(CAMS),--depth cam$(c) $(call depth,$(c))) > $(@D)/summary.txt
SHOW_COMPRESSION = echo "views and depth maps coded with x265 at QP 22 to 37, one atlas against one by one:"; \
    grep '^packed against' $(CHAIN)/compression/summary.txt
NO_COMPRESSION = echo "x265 or ffmpeg not installed (apt-get install x265 ffmpeg): no rate-distortion run"

chain: $(foreach c,$(INNER),$(CHAIN)/synthesized_v$(c).scores) $(DEPTH_ERRORS) \
		$(VIRTUAL_VIEWS) $(CHAIN)/atlas.yuv $(if $(CHUNK_STARTS),$(CHUNKS)/checked) \
		$(if $(HAVE_ENCODERS),$(CHAIN)/compression/report.json)
	@echo "estimated depth against the truth, as disparity towards a neighbour (bad 1, bad 2:"
	@echo "% of pixels off by more than 1 and 2 px; mean abs and RMS error, px; mean of the frames):"
	@for c in $(CAMS); do printf 'cam%s ' $$c; grep '^  mean' $(CHAIN)/estimated_v$${c}_depth.errors.txt; done
	@echo "each inner camera left out and synthesized from its rectified, colour-corrected"
	@echo "neighbours and their estimated depth (Y-PSNR U V YUV Y-SSIM IV-PSNR, mean of the frames):"
	@for c in $(INNER); do printf 'cam%s ' $$c; grep '^  mean' $(CHAIN)/synthesized_v$$c.scores; done
	@echo "virtual views halfway between neighbours: $(notdir $(VIRTUAL_VIEWS))"
	@$(if $(CHUNK_STARTS),cat $(CHUNKS)/checked)
	@$(if $(HAVE_ENCODERS),$(SHOW_COMPRESSION),$(NO_COMPRESSION))
	$(BIN)/mvtools bitrate --size 1920x1080 --fps 25 --views 9

# Published material (../shared/data, or DATA=...): depth estimated for the two outer views
# of a Middlebury triple from that pair, the middle view synthesized from them (1D mode)
# and scored against the real one; and Kendo's camera 2 synthesized from cameras 1 and 3
# with the configuration shipped with the sequence (no real camera 2 is shipped to score).
DATA ?= ../shared/data
PUBLISHED := $(BUILD)/published
MIDDLEBURY := configs/middlebury
THRESHOLDS := $(MIDDLEBURY)/published_thresholds.txt

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
	    --disparity-of right --disparities $(4) -o $$@

$$($(1)_out)/%_depth_$(6)_yuv420p.yuv: $$($(1)_out)/%.pfm
	$(BIN)/mvtools convert $$< --from disparity --focal 1 --baseline $(5) \
	    --depth-range $$($(1)_znear) $$($(1)_zfar) -o $$@

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

# Cones im2's estimated disparity against its ground truth (the pair's own, disp2)
$(PUBLISHED)/cones/im2.errors.json: $(PUBLISHED)/cones/im2.pfm
	$(BIN)/mvtools evaluate --disparity $(DATA)/middlebury/2003/cones/disp2.png $< \
	    --json-file $@ > $(@:.json=.txt)

KENDO := $(DATA)/mpeg/kendo
$(PUBLISHED)/kendo/synthesized_02_1024x768_yuv420p.yuv: $(KENDO)/config/VSRS/vsrs_kendo_ori.cfg | install
	mkdir -p $(@D)
	$(BIN)/mvtools synthesize $< --data-dir $(KENDO) -o $@

# every program run for these targets notes its time (the last run of each output counts)
published: export MVTOOLS_TIME_LOG := $(abspath $(PUBLISHED))/stage_times.tsv
published: $(PUBLISHED)/cones/cones.scores $(PUBLISHED)/tsukuba/tsukuba.scores \
		$(PUBLISHED)/cones/im2.errors.json $(PUBLISHED)/kendo/synthesized_02_1024x768_yuv420p.yuv
	@echo "seconds per stage (program, output):"
	@awk -F '\t' '{ time[$$2 "\t" $$3] = $$1 } END { for (key in time) { split(key, part, "\t"); \
	    printf "%8.2f  %-24s %s\n", time[key], part[1], part[2] } }' $(MVTOOLS_TIME_LOG) | sort -k4
	@echo "published material: the middle view synthesized from the depth estimated for the outer pair"
	@for case in cones tsukuba; do printf '%-8s ' $$case; \
	    grep '^  mean' $(PUBLISHED)/$$case/$$case.scores; done
	@echo "(columns: Y-PSNR U-PSNR V-PSNR YUV-PSNR Y-SSIM IV-PSNR, dB)"
	@echo "against the least accepted ($(THRESHOLDS)):"
	@awk '!/^#/ && NF == 3 { file = "$(PUBLISHED)/" $$1 "/" $$1 ".scores"; y = iv = 0; \
	    while ((getline line < file) > 0) if (line ~ /^  mean/) { split(line, f, " "); \
	        y = f[2]; iv = f[7] } \
	    ok = y >= $$2 && iv >= $$3; failed += !ok; \
	    printf "%-8s Y-PSNR %6.2f (least %5.2f)  IV-PSNR %6.2f (least %5.2f)  %s\n", \
	        $$1, y, $$2, iv, $$3, ok ? "ok" : "BELOW" } END { exit failed > 0 }' $(THRESHOLDS)
	@echo "the depth behind the Cones scores: im2's disparity against its ground truth"
	@cat $(PUBLISHED)/cones/im2.errors.txt
	@echo "kendo: camera 2 synthesized from cameras 1 and 3: $(PUBLISHED)/kendo/synthesized_02_1024x768_yuv420p.yuv"
	$(BIN)/mvtools report $(PUBLISHED)

# The suite runs a test file per worker, a worker per core up to four (pytest-xdist): on
# CI's two cores 6 1/2 minutes instead of 9 1/2 file after file. A file keeps to one
# worker, so its module fixtures (a pipeline's outputs) are made once.
# `make test TEST_WORKERS=0` runs every test in one process, one after another.
TEST_WORKERS ?= auto
PYTEST = $(BIN)/python -m pytest -q -n $(TEST_WORKERS) --maxprocesses 4 --dist loadfile

test: install
	$(PYTEST)

# The edit-test loop: everything but the tests marked slow (pipelines, corpus-wide runs)
# and those reading the published material (marked data by tests/conftest.py).
test-fast: install
	$(PYTEST) -m "not slow and not data"

# ruff's lint and format rules are in pyproject.toml
lint: install
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

bench: install
	$(BIN)/python benchmarks/run.py

clean:
	rm -rf $(BUILD)
