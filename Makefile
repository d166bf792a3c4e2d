# mvtools: the project's entry points. `make demo` and `make test` are the README's two commands.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
BUILD ?= build

.DELETE_ON_ERROR:
.PHONY: install sample demo chain test bench clean

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
	@echo "demo outputs in $(DEMO)"

# The chain on the array as built (sample_data/distorted: lens distortion, turned cameras,
# colour mismatch): calibrate the sample rig from its checkerboard captures, rectify the
# array, correct its colours to camera 2, estimate the depth of cameras 1 and 3 from their
# neighbours, synthesize camera 2 from them in 1D mode, score it against the real one,
# and pack views and depth maps into one atlas.
CHAIN := $(DEMO)/chain
DISTORTED := sample_data/distorted
CAMS := 0 1 2 3 4
chain: install
	mkdir -p $(CHAIN)
	$(BIN)/mvtools calibrate $(foreach c,$(CAMS),sample_data/checkerboard/cam$(c)) --board 9x6 \
	    --square 0.05 -o $(CHAIN)/calibrated_rig.txt --report $(CHAIN)/calibration
	$(BIN)/mvtools rectify $(DISTORTED)/cameras.txt -o $(CHAIN)/rectified \
	    $(foreach c,$(CAMS),--texture cam$(c) $(DISTORTED)/v$(c)_texture_$(VIEW))
	$(BIN)/mvtools colorcorrect --reference cam2 --cameras $(CHAIN)/rectified/cameras.txt \
	    --depth-range 2 13 -o $(CHAIN)/corrected \
	    $(foreach c,$(CAMS),--view cam$(c) $(CHAIN)/rectified/v$(c)_texture_$(VIEW))
	$(foreach c,1 3,$(BIN)/mvtools estimate-depth $(LINE)/depth_cam2.cfg \
	    FileCameraParameter=$(CHAIN)/rectified/cameras.txt LeftCameraName=cam$(shell expr $(c) - 1) \
	    CenterCameraName=cam$(c) RightCameraName=cam$(shell expr $(c) + 1) \
	    FileLeftViewImage=$(CHAIN)/corrected/v$(shell expr $(c) - 1)_texture_$(VIEW) \
	    FileCenterViewImage=$(CHAIN)/corrected/v$(c)_texture_$(VIEW) \
	    FileRightViewImage=$(CHAIN)/corrected/v$(shell expr $(c) + 1)_texture_$(VIEW) \
	    FileOutputDepthMapImage=$(CHAIN)/estimated_v$(c)_depth_$(VIEW) &&) true
	$(BIN)/mvtools synthesize $(LINE)/synthesize_cam2.cfg CameraParameterFile=$(CHAIN)/rectified/cameras.txt \
	    LeftViewImageName=$(CHAIN)/corrected/v1_texture_$(VIEW) RightViewImageName=$(CHAIN)/corrected/v3_texture_$(VIEW) \
	    LeftDepthMapName=$(CHAIN)/estimated_v1_depth_$(VIEW) RightDepthMapName=$(CHAIN)/estimated_v3_depth_$(VIEW) \
	    -o $(CHAIN)/synthesized_v2_$(VIEW)
	$(BIN)/mvtools evaluate $(CHAIN)/corrected/v2_texture_$(VIEW) $(CHAIN)/synthesized_v2_$(VIEW)
	$(BIN)/mvtools pack --layout atlas -o $(CHAIN)/atlas.yuv \
	    $(foreach c,1 2 3,--view cam$(c) $(CHAIN)/corrected/v$(c)_texture_$(VIEW)) \
	    $(foreach c,1 3,--depth cam$(c) $(CHAIN)/estimated_v$(c)_depth_$(VIEW))
	$(BIN)/mvtools bitrate --size 1920x1080 --fps 25 --views 9

test: install
	$(BIN)/python -m pytest -q

bench: install
	$(BIN)/python benchmarks/run.py

clean:
	rm -rf $(BUILD)
