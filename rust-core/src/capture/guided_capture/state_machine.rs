//! The transitions of [`GuidedCapture`].

use super::*;

impl Step {
    /// What the app shows for this step.
    pub fn instruction<'a>(&self, config: &'a GuidedCaptureConfig) -> &'a str {
        match self {
            Step::Neutral => "Relax your face, look at the screen and hold still",
            Step::Expression(shape) => instruction(*shape),
            Step::Test(i) => config
                .tests
                .get(*i)
                .map(|t| t.instruction.as_str())
                .unwrap_or(""),
        }
    }
}

impl Step {
    /// Its name in reports: `neutral`, the ARKit name, or the test's id.
    pub fn name(&self, config: &GuidedCaptureConfig) -> String {
        match self {
            Step::Neutral => "neutral".to_string(),
            Step::Expression(shape) => shape.name().to_string(),
            Step::Test(i) => config
                .tests
                .get(*i)
                .map(|t| t.id.clone())
                .unwrap_or_else(|| format!("test {i}")),
        }
    }
}

impl GuidedCapture {
    /// A capture about to start with the neutral scan. Call
    /// [`GuidedCapture::start`] for the first [`CaptureEvent::Started`].
    pub fn new(config: GuidedCaptureConfig) -> GuidedCapture {
        GuidedCapture {
            queue: config.steps().collect(),
            neutral_detector: NeutralDetector::new(config.neutral),
            rest: RestLevels::NONE,
            tests: vec![None; config.tests.len()],
            config,
            active: None,
            retained: VecDeque::new(),
            untracked: VecDeque::new(),
            neutral: None,
            expressions: vec![None; PROMPT_ORDER.len()],
            skipped: Vec::new(),
            frames_seen: 0,
            last_timestamp: None,
            vertex_count: None,
        }
    }

    /// The configuration.
    pub fn config(&self) -> &GuidedCaptureConfig {
        &self.config
    }

    /// Begins the first step (the neutral scan); a no-op once started.
    pub fn start(&mut self) -> Vec<CaptureEvent> {
        let mut events = Vec::new();
        if self.active.is_none() && self.frames_seen == 0 {
            self.advance(&mut events);
        }
        events
    }

    /// Feeds the next frame of the stream (starting the capture if
    /// [`GuidedCapture::start`] was not called). Frames after the last step
    /// are counted and otherwise ignored. On error nothing changes.
    pub fn push(&mut self, frame: Frame) -> Result<Vec<CaptureEvent>, GuidedCaptureError> {
        self.check(&frame)?;
        let mut events = self.start();
        let index = self.frames_seen;
        self.frames_seen += 1;
        self.last_timestamp = Some(frame.timestamp);
        if !frame.tracked {
            self.untracked.push_back(index);
        }
        let Some(active) = self.active.as_mut() else {
            return Ok(events);
        };
        let started_at = *active.started_at.get_or_insert(frame.timestamp);
        let timed_out = frame.timestamp - started_at > self.config.step_timeout;
        match active.step {
            Step::Neutral => {
                if let Some(scan) = self.neutral_detector.push(index, frame) {
                    let threshold = self.config.peak.threshold;
                    self.rest =
                        RestLevels::from_neutral(&scan.rest, self.config.rest_floor, threshold);
                    let quality = CaptureQuality {
                        high_rest: RestLevels::from_neutral(&scan.rest, 0.0, threshold)
                            .highest_above(self.config.neutral.max_weight),
                        ..CaptureQuality::default()
                    };
                    self.neutral = Some(self.capture(scan.index, scan.frame, quality));
                    self.finish_step(Step::Neutral, scan.index, quality, &mut events);
                }
            }
            step => {
                let value = match step {
                    Step::Expression(shape) => self.rest.relative(shape, frame.weights.get(shape)),
                    _ if frame.tracked => {
                        let baseline = active.baseline.get_or_insert(frame.weights);
                        for (b, w) in baseline.0.iter_mut().zip(&frame.weights.0) {
                            if w.is_finite() {
                                *b = b.min(*w);
                            }
                        }
                        test_intensity(&frame.weights, baseline)
                    }
                    _ => 0.0,
                };
                let mut peak = None;
                let detector_index = frame.tracked.then(|| {
                    peak = active.detector.push(value);
                    active.fed += 1;
                    active.fed - 1
                });
                self.retained.push_back(Retained {
                    index,
                    detector_index,
                    frame,
                });
                if let Some(peak) = peak {
                    let at = self.peak_frame(step, &peak);
                    self.capture_peak(step, at, &mut events);
                } else if timed_out {
                    self.skip_step(SkipReason::TimedOut, &mut events);
                } else {
                    self.forget_unneeded();
                }
            }
        }
        Ok(events)
    }

    /// Skips the step under way (not the neutral scan).
    pub fn skip(&mut self) -> Result<Vec<CaptureEvent>, GuidedCaptureError> {
        let mut events = Vec::new();
        match self.active.as_ref().map(|a| a.step) {
            Some(Step::Neutral) => return Err(GuidedCaptureError::NeutralNotSkippable),
            Some(_) => self.skip_step(SkipReason::Requested, &mut events),
            None => {}
        }
        Ok(events)
    }

    /// Asks for `step` again now; the step under way resumes afterwards. An
    /// earlier capture of `step` is kept until the retake captures. Works
    /// after [`CaptureEvent::Finished`] too (it finishes again).
    pub fn retake(&mut self, step: Step) -> Result<Vec<CaptureEvent>, GuidedCaptureError> {
        if let Step::Test(i) = step
            && i >= self.config.tests.len()
        {
            return Err(GuidedCaptureError::NoSuchTest(i, self.config.tests.len()));
        }
        if let Some(current) = self.active.take()
            && current.step != step
        {
            self.queue.push_front(current.step);
        }
        self.queue.retain(|s| *s != step);
        self.queue.push_front(step);
        let mut events = Vec::new();
        self.advance(&mut events);
        Ok(events)
    }

    /// The capture was interrupted (a call, the app sent to the
    /// background, the phone locked): the step under way starts again with
    /// the next frame, as if just asked for, so the time away neither
    /// times it out nor joins its peak to frames from before. Its
    /// [`CaptureEvent::Started`] is given again; nothing if no step is under
    /// way.
    pub fn interrupt(&mut self) -> Vec<CaptureEvent> {
        let mut events = Vec::new();
        if let Some(current) = self.active.take() {
            self.queue.push_front(current.step);
            self.advance(&mut events);
        }
        events
    }

    /// Ends the capture now: the step under way and every step still
    /// queued are skipped ([`SkipReason::CaptureEnded`]), what was captured
    /// is kept, and [`CaptureEvent::Finished`] follows. A retake after it
    /// is the caller's to refuse.
    pub fn end(&mut self) -> Vec<CaptureEvent> {
        let mut events = Vec::new();
        if self.active.is_none() {
            return events;
        }
        for step in std::mem::take(&mut self.queue) {
            if self.capture_of(step).is_none() && !self.skipped.contains(&step) {
                self.skipped.push(step);
            }
        }
        self.skip_step(SkipReason::CaptureEnded, &mut events);
        events
    }

    /// How far along the capture is.
    pub fn progress(&self) -> Progress {
        let captured = usize::from(self.neutral.is_some())
            + self.expressions.iter().flatten().count()
            + self.tests.iter().flatten().count();
        Progress {
            total: 1 + self.expressions.len() + self.tests.len(),
            captured,
            skipped: self.skipped.len(),
            current: self.active.as_ref().map(|a| a.step),
        }
    }

    /// The capture of `step`, if any.
    pub fn capture_of(&self, step: Step) -> Option<&Capture> {
        // Indexing, here and in `slot`: `expressions` has one slot per entry
        // of PROMPT_ORDER, and `prompt_index` is below that for every shape.
        match step {
            Step::Neutral => self.neutral.as_ref(),
            Step::Expression(shape) => self.expressions[prompt_index(shape)].as_ref(),
            Step::Test(i) => self.tests.get(i)?.as_ref(),
        }
    }

    /// Where the capture of `step` is kept (`None` for an unknown test).
    fn slot(&mut self, step: Step) -> Option<&mut Option<Capture>> {
        match step {
            Step::Neutral => Some(&mut self.neutral),
            Step::Expression(shape) => Some(&mut self.expressions[prompt_index(shape)]),
            Step::Test(i) => self.tests.get_mut(i),
        }
    }

    /// Steps skipped without a capture, in the order they were skipped.
    pub fn skipped(&self) -> &[Step] {
        &self.skipped
    }

    /// Frames fed so far.
    pub fn frames_seen(&self) -> u64 {
        self.frames_seen
    }

    fn check(&self, frame: &Frame) -> Result<(), GuidedCaptureError> {
        let index = self.frames_seen;
        if !frame.timestamp.is_finite() {
            return Err(GuidedCaptureError::BadTimestamp {
                frame: index,
                timestamp: frame.timestamp,
            });
        }
        if let Some(previous) = self.last_timestamp
            && frame.timestamp < previous
        {
            return Err(GuidedCaptureError::TimeWentBack {
                frame: index,
                timestamp: frame.timestamp,
                previous,
            });
        }
        if let (Some(expected), Some(mesh)) = (self.vertex_count, &frame.vertices)
            && mesh.len() != expected
        {
            return Err(GuidedCaptureError::VertexCount {
                frame: index,
                expected,
                found: mesh.len(),
            });
        }
        Ok(())
    }

    /// The detector frame to capture for `peak` of `step`: its frame,
    /// unless the weight was saturated over a stretch; then the companion
    /// weights or the mesh tell where the face peaked
    /// ([`saturated_peak`](super::saturated_peak)).
    fn peak_frame(&self, step: Step, peak: &Peak) -> usize {
        let (Some((first, last)), Step::Expression(shape)) = (peak.saturated, step) else {
            return peak.frame;
        };
        let latency = self.config.peak.latency_frames.max(0.0).round() as usize;
        let within = |from: usize, to: usize| -> Vec<StretchFrame> {
            self.retained
                .iter()
                .filter_map(|r| {
                    let at = r.detector_index.filter(|i| (from..=to).contains(i))?;
                    Some((at, &r.frame))
                })
                .collect()
        };
        let stretch = within(first, last);
        let lagged = within(first + latency, last + latency);
        let rest = self.neutral.as_ref().map_or(Weights::ZERO, |n| n.weights);
        let neutral = self.neutral.as_ref().and_then(|n| n.vertices.as_deref());
        saturated_peak::peak_in_stretch(shape, &stretch, &lagged, latency, &rest, neutral)
            .unwrap_or(peak.frame)
    }

    /// Records the peak at detector frame `at` as the capture of `step`.
    fn capture_peak(&mut self, step: Step, at: usize, events: &mut Vec<CaptureEvent>) {
        let position = self
            .retained
            .iter()
            .position(|r| r.detector_index == Some(at));
        let Some(retained) = position.and_then(|p| self.retained.remove(p)) else {
            // The detector only reports frames it still holds; a miss would
            // be a bug, and losing a capture is better than a crash.
            self.skip_step(SkipReason::TimedOut, events);
            return;
        };
        let mut quality = match step {
            Step::Expression(shape) => capture_quality::assess(
                shape,
                &self.rest.relative_weights(&retained.frame.weights),
                &self.config.quality,
            ),
            _ => CaptureQuality::default(),
        };
        let margin = self.config.quality.tracking_margin;
        quality.tracking_lost = self
            .untracked
            .iter()
            .any(|u| u.abs_diff(retained.index) <= margin);
        let capture = self.capture(retained.index, retained.frame, quality);
        if let Some(slot) = self.slot(step) {
            *slot = Some(capture);
        }
        self.finish_step(step, retained.index, quality, events);
    }

    fn capture(&mut self, index: u64, frame: Frame, quality: CaptureQuality) -> Capture {
        if let Some(mesh) = &frame.vertices {
            self.vertex_count.get_or_insert(mesh.len());
        }
        Capture {
            frame: index,
            timestamp: frame.timestamp,
            weights: frame.weights,
            vertices: frame.vertices,
            quality,
        }
    }

    fn finish_step(
        &mut self,
        step: Step,
        frame: u64,
        quality: CaptureQuality,
        events: &mut Vec<CaptureEvent>,
    ) {
        self.skipped.retain(|s| *s != step);
        events.push(CaptureEvent::Captured {
            step,
            frame,
            quality,
        });
        self.advance(events);
    }

    fn skip_step(&mut self, reason: SkipReason, events: &mut Vec<CaptureEvent>) {
        let Some(active) = self.active.as_ref() else {
            return;
        };
        let step = active.step;
        if self.capture_of(step).is_none() && !self.skipped.contains(&step) {
            self.skipped.push(step);
        }
        events.push(CaptureEvent::Skipped { step, reason });
        self.advance(events);
    }

    /// Starts the next queued step, or finishes.
    fn advance(&mut self, events: &mut Vec<CaptureEvent>) {
        self.retained.clear();
        self.neutral_detector = NeutralDetector::new(self.config.neutral);
        self.active = self.queue.pop_front().map(|step| {
            let config = match step {
                Step::Test(_) => self.config.test_peak,
                _ => self.config.peak,
            };
            events.push(CaptureEvent::Started(step));
            Active {
                step,
                detector: PeakDetector::new(config),
                fed: 0,
                started_at: None,
                baseline: None,
            }
        });
        if self.active.is_none() {
            let progress = self.progress();
            events.push(CaptureEvent::Finished {
                captured: progress.captured,
                skipped: progress.total - progress.captured,
            });
        }
    }

    /// Drops retained frames no capture can use any more.
    fn forget_unneeded(&mut self) {
        let Some(active) = self.active.as_ref() else {
            return;
        };
        let needed = active.detector.oldest_needed();
        while let Some(front) = self.retained.front() {
            match front.detector_index {
                Some(d) if d >= needed => break,
                _ => {
                    self.retained.pop_front();
                }
            }
        }
        let oldest = self
            .retained
            .front()
            .map(|r| r.index)
            .unwrap_or(self.frames_seen);
        let margin = self.config.quality.tracking_margin;
        while self.untracked.front().is_some_and(|u| u + margin < oldest) {
            self.untracked.pop_front();
        }
    }
}

/// Position of `shape` in [`PROMPT_ORDER`], which holds every shape once.
fn prompt_index(shape: Blendshape) -> usize {
    PROMPT_ORDER
        .iter()
        .position(|s| *s == shape)
        .unwrap_or(shape.index())
}
