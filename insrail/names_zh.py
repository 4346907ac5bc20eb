"""Simplified Chinese (zh-CN) of every text the reports, the exports and the display-name tables print.

English wording (as written in the code, the key) -> Chinese; :func:`insrail.names.t` looks it up. The field's
standard terms, as the thesis (Chen 2016, Figure 5-7) and TB 10754-2018 use them: 轨距 gauge, 水平 cross level,
超高 cant, 轨向 alignment, 高低 longitudinal level, 扭曲 (三角坑) twist, 轨距变化率 gauge change rate, 30 m 弦 5 m
检测 the 30 m / 5 m check (短波不平顺), 300 m 弦 150 m 检测 (长波不平顺), 正矢 versine, 调整量 adjustment amount,
里程 chainage, 轨枕 sleeper, 超限 exceedance, 偏差 deviation (实测 − 设计/最优). A template keeps its
English fields ({count}, {chord_m:g}); ``tests/test_languages.py`` checks that and that no text lacks its entry.
"""

ZH_CN: dict[str, str] = {
    # ------------------------------------------------------------------ display-name tables (insrail.names)
    "Gauge": "轨距",
    "Gauge deviation": "轨距偏差",
    "Cross level": "水平",
    "Cant": "超高",
    "Design cant": "设计超高",
    "Twist": "扭曲（三角坑）",
    "Twist 3 m": "扭曲（三角坑）3 m",
    "Twist {base_m:g} m{twist_of}": "扭曲（三角坑）{base_m:g} m{twist_of}",
    "Twist {base_ft:g} ft{twist_of}": "扭曲（三角坑）{base_ft:g} ft{twist_of}",
    " of the measured cant": "（实测超高）",
    "Gauge change rate {base}": "轨距变化率 {base}",
    "Gauge change rate 2.5 m": "轨距变化率 2.5 m",
    "Gauge change to the previous sleeper": "轨距邻点递变",
    "sleeper to sleeper": "相邻轨枕",
    "{chord_m:g} m versine": "{chord_m:g} m 弦正矢",
    "{chord_m:g} m / {pair_m:g} m differential versine": "{chord_m:g} m 弦 {pair_m:g} m 检测差分正矢",
    "{chord_m:g} m / {pair_m:g} m short wave": "短波不平顺（{chord_m:g} m 弦 {pair_m:g} m 检测）",
    "{chord_m:g} m / {pair_m:g} m long wave": "长波不平顺（{chord_m:g} m 弦 {pair_m:g} m 检测）",
    "{band} band peak": "{band} 波段峰值",
    "Cant change rate {base}": "超高变化率 {base}",
    "Alignment and height change rate {base}": "轨向与高低变化率 {base}",
    "Cant deficiency": "欠超高",
    "Cant deficiency rate {base}": "欠超高变化率 {base}",
    "Alignment {chord_ft:g} ft chord": "轨向 {chord_ft:g} ft 弦",
    "Profile {chord_ft:g} ft chord": "高低 {chord_ft:g} ft 弦",
    "Alignment {band}": "轨向 {band}",
    "Longitudinal level {band}": "高低 {band}",
    "left rail": "左轨",
    "right rail": "右轨",
    "lateral": "横向",
    "vertical": "垂向",
    "left rail, lateral": "左轨向",
    "right rail, lateral": "右轨向",
    "left rail, vertical": "左高低",
    "right rail, vertical": "右高低",
    "Sleeper number": "轨枕编号",
    "Chainage": "里程",
    "Station": "测站里程",
    "GPS time of week": "GPS 周内秒",
    "Detected by the sleeper sensor": "轨枕传感器检出",
    "Valid sleeper": "有效轨枕",
    "Not assessed because": "未评估原因",
    "Broken-chainage zone": "断链属性",
    "Left rail easting": "左轨东坐标",
    "Left rail northing": "左轨北坐标",
    "Left rail height": "左轨高程",
    "Right rail easting": "右轨东坐标",
    "Right rail northing": "右轨北坐标",
    "Right rail height": "右轨高程",
    "Guiding rail": "导向轨",
    "Centreline easting": "中线东坐标",
    "Centreline northing": "中线北坐标",
    "Centreline height": "中线高程",
    "Roll": "横滚角",
    "Pitch": "俯仰角",
    "Heading": "航向角",
    "Line speed": "线路速度",
    "Curvature": "曲率",
    "Cant change rate": "超高变化率",
    "Alignment change rate, left rail": "轨向变化率，左轨",
    "Alignment change rate, right rail": "轨向变化率，右轨",
    "Height change rate, left rail": "高低变化率，左轨",
    "Height change rate, right rail": "高低变化率，右轨",
    "Cant deficiency rate": "欠超高变化率",
    "Lateral deviation, left rail": "左轨向偏差",
    "Lateral deviation, right rail": "右轨向偏差",
    "Vertical deviation, left rail": "左高低偏差",
    "Vertical deviation, right rail": "右高低偏差",
    "Lateral adjustment, left rail": "左轨横向调整量",
    "Lateral adjustment, right rail": "右轨横向调整量",
    "Vertical adjustment, left rail": "左轨垂向调整量",
    "Vertical adjustment, right rail": "右轨垂向调整量",
    "Lateral checks still failed after adjustment, left rail": "调整后仍超限的横向检测，左轨",
    "Lateral checks still failed after adjustment, right rail": "调整后仍超限的横向检测，右轨",
    "Vertical checks still failed after adjustment, left rail": "调整后仍超限的垂向检测，左轨",
    "Vertical checks still failed after adjustment, right rail": "调整后仍超限的垂向检测，右轨",
    "Row": "序号",
    "Runs": "测次",
    "Checks still failed after adjustment": "调整后仍超限",
    "Share of run {survey}": "测次 {survey} 的权重",
    "Longitudinal level, left rail": "左高低",
    "Longitudinal level, right rail": "右高低",
    "Alignment, left rail": "左轨向",
    "Alignment, right rail": "右轨向",
    "Track quality index (TQI)": "轨道质量指数（TQI）",
    "Predicted 1σ, lateral position": "预测 1σ，横向位置",
    "Predicted 1σ, vertical position": "预测 1σ，垂向位置",
    "Predicted 1σ, 5 m lag difference, lateral": "预测 1σ，5 m 间隔差，横向",
    "Predicted 1σ, 5 m lag difference, vertical": "预测 1σ，5 m 间隔差，垂向",
    "Predicted 1σ, 150 m lag difference, lateral": "预测 1σ，150 m 间隔差，横向",
    "Predicted 1σ, 150 m lag difference, vertical": "预测 1σ，150 m 间隔差，垂向",
    "Predicted 1σ, cross-level (cant)": "预测 1σ，水平（超高）",
    "Predicted 1σ, along-track position": "预测 1σ，沿线位置",
    # project.toml settings
    "Project name": "项目名称",
    "Description": "说明",
    "Coordinate system": "坐标系",
    "Ellipsoid": "椭球",
    "Semi-major axis (custom ellipsoid)": "长半轴（自定义椭球）",
    "Inverse flattening (custom ellipsoid)": "扁率倒数（自定义椭球）",
    "Central meridian": "中央子午线",
    "Latitude of origin": "原点纬度",
    "Scale factor": "比例因子",
    "False easting": "东偏移",
    "False northing": "北偏移",
    "Projection height": "投影面高程",
    "Projection height applied as": "投影面高程的处理方式",
    "Mean earth radius": "地球平均半径",
    "Benchmarks file": "水准点文件",
    "Height-anomaly model": "高程异常模型",
    "Geoid grid": "大地水准面格网",
    "Trolley geometry": "小车几何参数",
    "IMU → GNSS antenna": "IMU → GNSS 天线",
    "IMU → odometer wheel contact": "IMU → 里程计轮接触点",
    "IMU → second (right) odometer wheel contact": "IMU → 第二（右侧）里程计轮接触点",
    "IMU → reference rail gauge point": "IMU → 基准轨轨距点",
    "IMU → sleeper detector": "IMU → 轨枕传感器",
    "IMU → prism": "IMU → 棱镜",
    "Mounting roll, pitch, heading": "安装横滚、俯仰、航向",
    "Reference rail": "基准轨",
    "Rail centre spacing": "两轨中心距",
    "No adjustment amounts: a relative survey (no GNSS, no prism fixes) knows the track's shape, not its place against the design; amounts would move the rails by the IMU's drift":
        "无调整量：相对测量（无 GNSS、无棱镜定位）只测得轨道形状，不知其相对设计线形的位置；调整量会按惯导漂移移动钢轨",
    "Gauge beam wheel spacing (curve correction)": "轨距测量梁轮距（曲线修正）",
    "Processing": "数据处理",
    "IMU profile": "IMU 误差模型",
    "Use the GNSS velocity": "使用 GNSS 速度",
    "Use the odometer": "使用里程计",
    "Non-holonomic constraints (NHC)": "非完整约束（NHC）",
    "Zero-velocity updates at stops (ZUPT)": "停车零速修正（ZUPT）",
    "RTS smoother": "RTS 平滑",
    "Filter update rate (Hz)": "滤波更新频率（Hz）",
    "GNSS sigma scale": "GNSS 标准差比例",
    "GNSS sigma floor (m)": "GNSS 标准差下限（m）",
    "GNSS error correlation time (s)": "GNSS 误差相关时间（s）",
    "Odometer sigma (m/s)": "里程计标准差（m/s）",
    "NHC sigma (m/s)": "NHC 标准差（m/s）",
    "ZUPT sigma where a stop shows no motion (m/s)": "静止时的 ZUPT 标准差（m/s）",
    "Shortest stop for a ZUPT (s)": "ZUPT 最短停车时间（s）",
    "Track": "线路",
    "Geodesy": "大地测量",
    "Control points": "控制点",
    "Report": "报告",
    "Client": "委托单位",
    "Line section": "线路区段",
    "Track (as the railway names it)": "股道（铁路的名称）",
    "Operator": "测量人员",
    "Checked by": "复核",
    "Approved by": "审批",
    "Trolley (make, model, serial number)": "小车（厂家、型号、编号）",
    "Trolley calibrated on": "小车检定日期",
    "IMU (make, model, serial number)": "IMU（厂家、型号、编号）",
    "IMU calibrated on": "IMU 检定日期",
    "Paper (landscape)": "纸张（横向）",
    "Language of the reports": "报告语言",
    "Design alignment": "设计线形",
    "Start station": "起点里程",
    "First sleeper number": "首枕编号",
    "Tolerance profile": "容许偏差标准",
    "Fastener type": "扣件类型",
    "Track events file": "线路事件文件",
    "Stationing direction": "里程方向",
    "Sleeper number anchor": "轨枕编号基准",
    "Line speed (km/h)": "线路速度（km/h）",
    "Surveys": "测量",
    "Survey name": "测量名称",
    "Survey folder": "测量文件夹",
    "Scale factor k × (1 + H0 / R)": "比例因子 k × (1 + H0 / R)",
    "Expanded ellipsoid, a + H0": "扩大椭球，a + H0",
    "Best fit to the benchmarks (leave-one-out)": "按水准点最佳拟合（留一法）",
    "Constant height anomaly": "常数高程异常",
    "Plane through the benchmarks": "水准点平面拟合",
    "Quadratic surface through the benchmarks": "水准点二次曲面拟合",
    "Left rail": "左轨",
    "Right rail": "右轨",
    "English": "英文",
    "Simplified Chinese": "简体中文",
    # shipped resources
    "High-speed ballastless track, static acceptance (TB 10754-2018)": "高速铁路无砟轨道静态验收（TB 10754-2018）",
    "Conventional main line > 160 km/h, maintenance work acceptance": "普速铁路正线 > 160 km/h，线路修理作业验收",
    "EN 13848-5 style isolated-defect template (values to be checked)": "EN 13848-5 式孤立缺陷模板（数值待核）",
    "FRA track Class 1 (49 CFR 213.53, 213.55, 213.63)": "FRA 1 级线路（49 CFR 213.53、213.55、213.63）",
    "FRA track Class 2 (49 CFR 213.53, 213.55, 213.63)": "FRA 2 级线路（49 CFR 213.53、213.55、213.63）",
    "FRA track Class 3 (49 CFR 213.53, 213.55, 213.63)": "FRA 3 级线路（49 CFR 213.53、213.55、213.63）",
    "FRA track Class 4 (49 CFR 213.53, 213.55, 213.63)": "FRA 4 级线路（49 CFR 213.53、213.55、213.63）",
    "FRA track Class 5 (49 CFR 213.53, 213.55, 213.63)": "FRA 5 级线路（49 CFR 213.53、213.55、213.63）",
    "WJ-7: lateral -6..+6 mm (stepless), vertical -4..+26 mm, 1 mm steps":
        "WJ-7：横向 -6..+6 mm（无级），垂向 -4..+26 mm，1 mm 级差",
    "WJ-8: lateral -5..+5 mm, vertical -4..+26 mm, 1 mm steps": "WJ-8：横向 -5..+5 mm，垂向 -4..+26 mm，1 mm 级差",
    "No sensor errors": "无传感器误差",
    "MEMS (ADIS16465 class): 2 deg/h in-run, 0.15 deg/sqrt(h), 0.037 m/s/sqrt(h)":
        "MEMS（ADIS16465 级）：零偏稳定性 2 deg/h，0.15 deg/sqrt(h)，0.037 m/s/sqrt(h)",
    "MEMS (ADIS16465 class) hand-held: noise 10 x the data sheet's for the hand's motion":
        "MEMS（ADIS16465 级）手持：噪声取手册值的 10 倍（手的晃动）",
    "Tactical FOG (KVH 1750 class): 0.05 deg/h in-run, 2 deg/h turn-on, 0.012 deg/sqrt(h)":
        "战术级光纤陀螺（KVH 1750 级）：零偏稳定性 0.05 deg/h，逐次启动 2 deg/h，0.012 deg/sqrt(h)",
    "Tactical grade: 1 deg/h, 0.1 deg/sqrt(h), 300 mGal, 300 ppm": "战术级：1 deg/h，0.1 deg/sqrt(h)，300 mGal，300 ppm",
    "Navigation grade (RLG, quartz accelerometers), thesis Table 3-2": "导航级（激光陀螺、石英加速度计），论文表 3-2",
    "49 CFR Part 213 §213.53 gauge, §213.55 alinement, §213.63 track surface":
        "49 CFR Part 213 §213.53 轨距，§213.55 轨向，§213.63 轨面",
    "EN 13848-1/-5 (bands), TSI INF 1299/2014 §4.2.8 (gauge, twist)":
        "EN 13848-1/-5（波段），TSI INF 1299/2014 §4.2.8（轨距、扭曲）",
    "TB 10754-2018 高速铁路轨道工程施工质量验收标准; thesis Chen 2016 Table 2-1":
        "TB 10754-2018 高速铁路轨道工程施工质量验收标准；论文 Chen 2016 表 2-1",
    "普速铁路线路修理规则, table 6.2.1 (作业验收, Vmax > 160 km/h)": "普速铁路线路修理规则，表 6.2.1（作业验收，Vmax > 160 km/h）",
    "insulating buffer pad": "绝缘缓冲垫板",
    "shims under the rail": "轨下调高垫板",
    "shims under the base plate": "铁垫板下调高垫板",
    "shim under the base plate": "铁垫板下调高垫板",
    "outer apron": "外侧轨距挡板",
    "outer block": "外侧轨距块",
    "inner block": "内侧轨距块",
    "inner apron": "内侧轨距挡板",
    "rail pad": "轨下垫板",
    "shift the base plate (no parts)": "移动铁垫板（无配件）",
    # adjustment strategies, events, severities
    "least total movement of both rails": "两轨总调整量最小",
    "move the guiding rail for line and the low rail for level; the other rail follows (only the gauge / cross-level "
    "change it needs counts)": "轨向调导向轨、高低调低轨，另一轨随之调整（只计其所需的轨距/水平变化）",
    "turnout": "道岔",
    "level crossing": "平交道口",
    "bridge": "桥梁",
    "joint": "钢轨接头",
    "not assessed": "不评估",
    "note": "备注",
    "severe": "严重",
    "major": "较大",
    "minor": "轻微",
    "severity by how far the peak lies beyond the limit: minor up to 25 %, major 25 - 100 %, severe over 100 % of "
    "the limit": "按峰值超出限值的程度分级：轻微不超过限值的 25 %，较大 25 - 100 %，严重超过 100 %",
    # ------------------------------------------------------------------ report texts (insrail.report, insrail.export)
    ".": "。",
    " and ": " 且 ",
    "yes": "是",
    "number": "轨枕编号",
    "L": "左",
    "R": "右",
    "left": "左轨",
    "right": "右轨",
    "no sleepers": "无轨枕",
    "chainage": "里程",
    "station m": "里程 m",
    "assessed with {profile}: {count} exceedances": "按 {profile} 评估：超限 {count} 处",
    "marked only": "仅标注",
    "no detector pulses: a regular grid": "无轨枕传感器脉冲：按等间距编号",
    "{pulses} pulses: {missed} missed sleepers inserted, {false} false pulses rejected":
        "{pulses} 个脉冲：补入漏检轨枕 {missed} 根，剔除误检脉冲 {false} 个",
    "versine, {chord_m:g} m chord": "正矢，{chord_m:g} m 弦",
    " ({back_m:g} m back)": "（后移 {back_m:g} m）",
    "differential versine, {chord_m:g} m chord / {pair_m:g} m pairs": "差分正矢，{chord_m:g} m 弦 {pair_m:g} m 检测点对",
    "band-passed peak, band {band}": "带通滤波峰值，波段 {band}",
    "twist over {base_m:g} m": "扭曲（三角坑），基长 {base_m:g} m",
    " (design cant ramp removed)": "（扣除设计超高顺坡）",
    "gauge change rate over {base_m:g} m": "轨距变化率，基长 {base_m:g} m",
    "gauge change rate sleeper to sleeper": "轨距变化率，相邻轨枕",
    "cant change rate over {base_m:g} m": "超高变化率，基长 {base_m:g} m",
    "cant deficiency rate over {base_m:g} m": "欠超高变化率，基长 {base_m:g} m",
    "alignment / height change rate over {base_m:g} m": "轨向/高低变化率，基长 {base_m:g} m",
    "gauge deviation from nominal": "轨距相对标准轨距的偏差",
    "cross-level (measured - design cant)": "水平（实测 - 设计超高）",
    "cant deficiency at line speed": "线路速度下的欠超高",
    "fastener type not readable: {error}": "扣件类型文件无法读取：{error}",
    "Sleeper": "轨枕",
    "Track parameters": "轨道参数",
    "Gauge and cross level [measured − nominal / design cant]": "轨距与水平 [实测 − 标准轨距/设计超高]",
    "Other checks of the tolerance profile": "容许偏差标准的其他检测项",
    "Adjustment (move the rail by)": "调整量（钢轨移动量）",
    "Action threshold {threshold:g} mm: every amount is 0 or at least this": "作业阈值 {threshold:g} mm：调整量为 0 或不小于此值",
    ", except at {count} sleepers where a smaller amount is needed to keep the checks":
        "，但有 {count} 根轨枕为满足检测需要较小的调整量",
    "After adjustment: {after} exceedances (before {before}), {new} where the track passed before":
        "调整后：超限 {after} 处（调整前 {before} 处），其中 {new} 处原本合格",
    "; sleepers still failing: {reasons}": "；仍超限的轨枕：{reasons}",
    "measured − design ({design})": "实测 − 设计（{design}）",
    "measured − fitted line": "实测 − 拟合线形",
    "Deviation [{reference}]": "偏差量 [{reference}]",
    "the design alignment {design}": "设计线形 {design}",
    "the line fitted to the measured centreline": "按实测中线拟合的线形",
    "lateral + right, vertical + up, looking towards increasing chainage": "面向里程增加方向：横向向右为正，垂向向上为正",
    "after it the track passes every check of tolerance profile {profile}": "调整后轨道满足容许偏差标准 {profile} 的全部检测项",
    " except at {count} sleepers marked as still failing": "，但标为仍超限的 {count} 根轨枕除外",
    "planned for tolerance profile {profile}, not re-assessed after the adjustment in these results":
        "按容许偏差标准 {profile} 计算，本结果未对调整后的轨道重新评估",
    "move the rail by the amount ({signs}); planned by insrail for fastener {fastener} in whole fastener steps "
    "({strategy}): {verdict}; it does not put the rail onto {reference}":
        "按调整量移动钢轨（{signs}）；由 insrail 按扣件 {fastener} 的整级调整计算（{strategy}）：{verdict}；"
        "调整后钢轨并不回到{reference}上",
    "survey {survey} {start}, {chainage}": "测量 {survey} {start}，{chainage}",
    "{project}, survey {survey} {start}, {chainage}, tolerance profile {profile}; {software}":
        "{project}，测量 {survey} {start}，{chainage}，容许偏差标准 {profile}；{software}",
    "{sleepers} ({valid} valid)": "{sleepers}（有效 {valid}）",
    "Project": "项目",
    "Line": "线路",
    "Survey": "测量",
    "Sleepers": "轨枕",
    "Survey start": "测量开始",
    "Standard": "标准",
    "Design": "设计",
    "fitted lines (no design alignment)": "拟合线形（无设计线形）",
    "Settings": "设置",
    "Nominal gauge": "标准轨距",
    "Software": "软件",
    "not stated": "未填写",
    "Track geometry per sleeper": "逐枕轨道几何参数",
    "Legend": "图例",
    "beyond a limit": "超限",
    "invalid sleeper": "无效轨枕",
    "Limits": "限值",
    "Deviations": "偏差量",
    "{reference}: where the rail is ({signs})": "{reference}：钢轨所在位置（{signs}）",
    "Adjustment": "调整",
    "limit {limits}": "限值 {limits}",
    "Adjustment sheet": "调整作业表",
    "The rails to move, in working order (increasing chainage). ": "需移动的钢轨，按作业顺序（里程增加）排列。",
    "Amounts: ": "调整量：",
    "Parts: outer = on the field side of the rail foot, inner = on the gauge side; No. 9→11: replace the No. 9 part "
    "by a No. 11; shims are added; * size assumed, not a published figure. The Materials sheet sums the parts.":
        "配件：外侧 = 轨底外侧，内侧 = 轨距内侧；9号→11号：以 11 号件替换 9 号件；垫板为加垫；* 为假定尺寸，"
        "非公布数值。材料表汇总所需配件。",
    "no.": "序号",
    "sleeper": "轨枕",
    "rail": "钢轨",
    "lateral (mm)": "横向（mm）",
    "vertical (mm)": "垂向（mm）",
    "fastener parts": "扣件配件",
    "checks still failed": "仍超限的检测",
    "Work section {number} of {count}: {first} – {last}, {sleepers} sleepers, {rails} rails to move":
        "作业段 {number}/{count}：{first} – {last}，轨枕 {sleepers} 根，需移动钢轨 {rails} 处",
    "no rail to move: every check of the tolerance profile passes as measured": "无需移动钢轨：实测即满足容许偏差标准的全部检测项",
    "{name}, steps of {step:g} mm": "{name}，级差 {step:g} mm",
    "{name} (the fastener type file is not readable: no parts)": "{name}（扣件类型文件无法读取：无配件）",
    "Fastener {kind}; total movement {movement:.0f} mm at {sleepers} sleepers; {failing} sleepers where the checks "
    "still fail": "扣件 {kind}；{sleepers} 根轨枕总调整量 {movement:.0f} mm；{failing} 根轨枕仍超限",
    "Materials list: the fastener parts the adjustment sheet needs": "材料表：调整作业表所需的扣件配件",
    "No parts for {note}": "无配件：{note}",
    "Parts marked * have sizes not taken from published figures: check them against the fastener type file before "
    "ordering.": "标 * 的配件尺寸非公布数值：订货前请对照扣件类型文件核对。",
    "part": "配件",
    "size": "规格",
    "left rails": "左轨",
    "right rails": "右轨",
    "total": "合计",
    "no parts: no sleeper to work on": "无配件：无需作业的轨枕",
    "no parts listed for this fastener type": "此扣件类型未列配件",
    "Exceedances, the most severe first, each severity in chainage order": "超限表：按严重程度排列，同级按里程排列",
    "severity": "严重程度",
    "check": "检测项",
    "what": "内容",
    "from": "起点",
    "to": "终点",
    "from (m)": "起点（m）",
    "to (m)": "终点（m）",
    "length (m)": "长度（m）",
    "peak": "峰值",
    "limit": "限值",
    "unit": "单位",
    "beyond the limit by (%)": "超出限值（%）",
    "first sleeper": "首枕",
    "last sleeper": "末枕",
    "Events: {count} measured sleepers not assessed with the tolerance profile": "线路事件：{count} 根实测轨枕未按容许偏差标准评估",
    "event": "事件",
    "text": "说明",
    "sleepers": "轨枕数",
    "assessment": "评估",
    "written in": "来源",
    "Summary": "汇总",
    "Statistics per parameter (valid sleepers)": "各参数统计（有效轨枕）",
    "parameter": "参数",
    "valid sleepers": "有效轨枕",
    "minimum": "最小值",
    "maximum": "最大值",
    "mean": "平均值",
    "standard deviation": "标准差",
    "sleepers beyond": "超限轨枕",
    "exceedances": "超限处数",
    "valid": "有效",
    "exceedances starting": "起始超限数",
    "SD {name} (mm)": "{name} 标准差（mm）",
    "TQI (mm)": "TQI（mm）",
    "Per {section:g} m section: the largest magnitude of every check of the profile (over its rails and directions), "
    "the standard deviations of the TQI channels ({band} band for level and alignment) and their sum, the TQI":
        "每 {section:g} m 区段：容许偏差标准各检测项的最大绝对值（取各轨、各方向），TQI 各项的标准差"
        "（高低与轨向取 {band} 波段）及其和，即 TQI",
    "{count} values (see the Summary sheet)": "{count} 个数值（见汇总表）",
    "Processing log": "处理记录",
    "summary.toml (QC figures of the processing)": "summary.toml（处理的质量控制数据）",
    "project.toml (settings)": "project.toml（设置）",
    "key": "键",
    "value": "值",
    "Report written": "报告生成时间",
    "Project file": "项目文件",
    "Results": "结果",
    "Note": "备注",
    "Materials": "材料",
    "Exceedances": "超限",
    "{project} – {survey}: track geometry": "{project} – {survey}：轨道几何",
    # PDF
    "page {number} of {pages}": "第 {number} 页，共 {pages} 页",
    "{name}; calibrated {date}": "{name}；检定日期 {date}",
    "{name}; calibration date not stated": "{name}；检定日期未填写",
    "not stated; error model {name}: {description}": "未填写；误差模型 {name}：{description}",
    "not stated (survey folder not readable)": "未填写（测量文件夹无法读取）",
    "Transverse Mercator on {ellipsoid} (a = {a:.3f} m, 1/f = {f:.9g}); central meridian {lon:g}°, latitude of "
    "origin {lat:g}°, scale factor {k:.9g}, false easting {east:.3f} m, false northing {north:.3f} m":
        "{ellipsoid} 上的高斯-克吕格（横轴墨卡托）投影（a = {a:.3f} m，1/f = {f:.9g}）；中央子午线 {lon:g}°，"
        "原点纬度 {lat:g}°，比例因子 {k:.9g}，东偏移 {east:.3f} m，北偏移 {north:.3f} m",
    "in the scale factor, mean radius {radius:.0f} m": "计入比例因子，地球平均半径 {radius:.0f} m",
    "on the semi-major axis": "计入长半轴",
    "; projection height {height:.3f} m ({convention})": "；投影面高程 {height:.3f} m（{convention}）",
    "ellipsoidal heights on {ellipsoid} (no benchmarks in the project: H = h)": "{ellipsoid} 大地高（项目无水准点：H = h）",
    "normal heights H = h - height anomaly, fitted ({model}) on the benchmarks of {benchmarks}":
        "正常高 H = h - 高程异常，按 {benchmarks} 的水准点拟合（{model}）",
    " over the geoid grid {grid} (remove-restore)": "，基于大地水准面格网 {grid}（移去-恢复）",
    "; benchmark RMS {rms:.1f} mm": "；水准点中误差 {rms:.1f} mm",
    ", leave-one-out {rms:.1f} mm": "，留一法 {rms:.1f} mm",
    "not recorded": "未记录",
    "towards increasing chainage ({first} to {last})": "里程增加方向（{first} 至 {last}）",
    "towards decreasing chainage ({first} to {last})": "里程减小方向（{first} 至 {last}）",
    "date not recorded": "日期未记录",
    "Direction of travel": "推行方向",
    "{chainage} ({length:.0f} m, {sleepers} sleepers, {valid} valid)": "{chainage}（{length:.0f} m，轨枕 {sleepers} 根，有效 {valid} 根）",
    "Trolley": "小车",
    "IMU": "IMU",
    "Height datum": "高程基准",
    "{design}; deviations {reference}": "{design}；偏差量 {reference}",
    "none: fitted line types, deviations {reference}": "无：拟合线形，偏差量 {reference}",
    "No sleeper is beyond a limit of tolerance profile {profile} ({valid} valid sleepers assessed).":
        "无轨枕超出容许偏差标准 {profile} 的限值（已评估有效轨枕 {valid} 根）。",
    "{count} more channels": "另有 {count} 个通道",
    "all channels": "全部通道",
    "{total} exceedance (runs of sleepers beyond a limit) in {valid} valid sleepers: {summary}.":
        "有效轨枕 {valid} 根中超限 {total} 处（连续超限的轨枕段）：{summary}。",
    "{total} exceedances (runs of sleepers beyond a limit) in {valid} valid sleepers: {summary}.":
        "有效轨枕 {valid} 根中超限 {total} 处（连续超限的轨枕段）：{summary}。",
    "channel": "通道",
    "all": "合计",
    "within the limit": "在限值内",
    "NOT within the limit": "超出限值",
    "Predicted accuracy: not available for these results (processed by an older insrail, or no differential-versine "
    "check in the profile).": "预测精度：本结果无此数据（由旧版 insrail 处理，或容许偏差标准无差分正矢检测项）。",
    "forward filter and RTS smoother": "前向滤波与 RTS 平滑",
    "forward filter only": "仅前向滤波",
    "forward filter": "前向滤波",
    "limit (mm)": "限值（mm）",
    "1σ median (mm)": "1σ 中位数（mm）",
    "3σ weakest (mm)": "最弱区段 3σ（mm）",
    "predicted": "预测结论",
    "From the fusion's error model along this survey ({passes}), per 200 m section; a check is met when 3σ of its "
    "weakest section is within the limit.": "由本次测量的融合误差模型（{passes}）按 200 m 区段计算；最弱区段的 3σ 在限值内即满足该检测项。",
    "{moving} sleepers to adjust ({fastener}); largest lateral {lateral}, vertical {vertical}; total movement {total}; ":
        "需调整轨枕 {moving} 根（{fastener}）；最大横向调整量 {lateral}，垂向 {vertical}；总调整量 {total}；",
    "{count} sleepers where the checks still fail after adjustment": "调整后仍超限的轨枕 {count} 根",
    "every check met after adjustment.": "调整后全部检测项合格。",
    "name": "姓名",
    "signature": "签字",
    "date": "日期",
    "Surveyed and processed by": "测量与数据处理",
    "Settings not recorded": "未记录设置",
    ": these results were {why}; this report states the project's settings as they are now.":
        "：本结果{why}；本报告列出项目当前的设置。",
    "processed before settings were recorded: process again to record them": "在记录设置之前处理：请重新处理以记录",
    "The project has changed since processing": "处理后项目已修改",
    "; this report states the settings the results were processed with: ": "；本报告列出处理结果时所用的设置：",
    "{count} warning from processing": "处理警告 {count} 条",
    "{count} warnings from processing": "处理警告 {count} 条",
    " (see Survey and processing): ": "（见“测量与数据处理”）：",
    "Track geometry survey report": "轨道几何测量报告",
    "Conclusion": "结论",
    "Predicted accuracy against the tolerances": "预测精度与容许偏差的比较",
    "Report written by {written} from the results of {folder}.": "报告由 {written} 根据 {folder} 的结果生成。",
    "Survey report": "测量报告",
    "not recorded in the results (processed by an older insrail)": "结果中未记录（由旧版 insrail 处理）",
    "; and {count} more": "；另有 {count} 段",
    "GNSS solutions": "GNSS 解",
    "{solutions} at {interval:g} s ({share:.1f} % of the survey span), {fixed} fixed":
        "{solutions} 个，间隔 {interval:g} s（占测量时段的 {share:.1f} %），固定解 {fixed} 个",
    "GNSS outages": "GNSS 中断",
    "{count} longer than 3 s, {total:.0f} s in all": "长于 3 s 的 {count} 段，共 {total:.0f} s",
    ": {listed} (GPS seconds of week)": "：{listed}（GPS 周内秒）",
    "Trajectory": "轨迹",
    "not available": "无",
    "{epochs} epochs, {start:.1f} - {end:.1f} s of week ({span:.0f} s), {passes}":
        "{epochs} 个历元，周内秒 {start:.1f} - {end:.1f}（{span:.0f} s），{passes}",
    "median {median:.1f} mm, 95 % {p95:.1f} mm, largest {max:.1f} mm": "中位数 {median:.1f} mm，95 % {p95:.1f} mm，最大 {max:.1f} mm",
    "Position sigma, horizontal": "位置标准差，水平方向",
    "Position sigma, vertical": "位置标准差，高程方向",
    "Odometer scale error": "里程计比例误差",
    "{last:+.2f} per mille at the end": "结束时 {last:+.2f} ‰",
    " (from {low:+.2f} to {high:+.2f} along the survey)": "（沿线 {low:+.2f} 至 {high:+.2f}）",
    "{epochs} epochs": "{epochs} 个历元",
    "Fusion": "组合导航",
    "{how}; {rejections} measurements rejected, {stops} stops (ZUPT)": "{how}；剔除观测 {rejections} 个，停车 {stops} 次（ZUPT）",
    "reused from the cache": "取自缓存",
    "computed": "已计算",
    "Heights": "高程",
    "{model} height-anomaly model": "{model} 高程异常模型",
    ", benchmark RMS {rms:.1f} mm (leave-one-out {loo:.1f} mm)": "，水准点中误差 {rms:.1f} mm（留一法 {loo:.1f} mm）",
    "Sleeper detector": "轨枕传感器",
    "Warning": "警告",
    "Survey and processing": "测量与数据处理",
    "Track quality per {section:g} m section (standard deviations, mm; level and alignment in the {band} band)":
        "每 {section:g} m 区段的轨道质量（标准差，mm；高低与轨向取 {band} 波段）",
    "section": "区段",
    "TQI": "TQI",
    "rotation {rotation_deg:.6f}°, scale {scale_ppm:+.2f} ppm, height shift {height_shift_m:+.4f} m":
        "旋转 {rotation_deg:.6f}°，尺度 {scale_ppm:+.2f} ppm，高程平移 {height_shift_m:+.4f} m",
    'rotations {rx_arcsec:.2f}" {ry_arcsec:.2f}" {rz_arcsec:.2f}", scale {scale_ppm:+.2f} ppm':
        '旋转 {rx_arcsec:.2f}" {ry_arcsec:.2f}" {rz_arcsec:.2f}"，尺度 {scale_ppm:+.2f} ppm',
    "{model} transformation on {points} common points: {what}; residual RMS {rms:.1f} mm, leave-one-out RMS {loo} mm; "
    "every coordinate in this report is in the local grid":
        "基于 {points} 个公共点的{model}转换：{what}；残差中误差 {rms:.1f} mm，留一法中误差 {loo} mm；"
        "本报告的全部坐标均为局部坐标",
    "Local control": "局部控制",
    "Local control: residuals of the common points (observed - transformed, mm)": "局部控制：公共点残差（观测 - 转换，mm）",
    "point": "点名",
    "east": "东",
    "north": "北",
    "height": "高程",
    "leave-one-out east": "留一法 东",
    "weakest section": "最弱区段",
    "1-sigma of the 5 m lag difference (30 m / 5 m check)": "5 m 间隔差的 1σ（30 m 弦 5 m 检测）",
    "1-sigma of the 150 m lag difference (300 m / 150 m check)": "150 m 间隔差的 1σ（300 m 弦 150 m 检测）",
    "weakest {rank}": "最弱 {rank}",
    "weakest": "最弱",
    "median": "中位数",
    "{count} sections": "{count} 个区段",
    "Predicted accuracy per section": "各区段预测精度",
    "1-sigma of the {passes} from the fusion's error model along this survey's measurements (its GNSS outages, stops "
    "and rejected data); lag differences are the errors behind the 30 m / 5 m and 300 m / 150 m checks. Shaded: the "
    "section whose figures stand furthest above the survey's median.":
        "按本次测量的观测（GNSS 中断、停车与剔除数据）由融合误差模型得到的{passes} 1σ；间隔差即 30 m 弦 5 m 检测"
        "与 300 m 弦 150 m 检测的误差来源。阴影：数值高出全线中位数最多的区段。",
    "1-sigma (mm)": "1σ（mm）",
    "position lateral": "横向位置",
    "position vertical": "垂向位置",
    "5 m lag lateral": "5 m 间隔 横向",
    "5 m lag vertical": "5 m 间隔 垂向",
    "150 m lag lateral": "150 m 间隔 横向",
    "150 m lag vertical": "150 m 间隔 垂向",
    "Lateral deviation, {reference}": "轨向偏差，{reference}",
    "Vertical deviation, {reference}": "高低偏差，{reference}",
    "measured": "实测",
    "design": "设计",
    "Charts {first} - {last}": "曲线图 {first} - {last}",
    "exceedance": "超限",
    "GNSS outage": "GNSS 中断",
    "Plan view": "平面图",
    "Plan view (engineering coordinates, stations in m)": "平面图（工程坐标，里程单位 m）",
    "centreline": "中线",
    "no coordinates": "无坐标",
    "Events and stretches not assessed": "线路事件与不评估地段",
    "{count} measured sleepers lie in events not assessed with the tolerance profile (greyed in the charts and the "
    "workbook, never counted as exceedances).": "{count} 根实测轨枕位于不按容许偏差标准评估的事件范围内（在曲线图和工作簿中以灰色显示，不计为超限）。",
    "No sleeper is beyond a limit of the tolerance profile.": "无轨枕超出容许偏差标准的限值。",
    "per mille": "‰",
    "beyond by": "超出",
    "lateral left (mm)": "左轨横向（mm）",
    "lateral right (mm)": "右轨横向（mm）",
    "vertical left (mm)": "左轨垂向（mm）",
    "vertical right (mm)": "右轨垂向（mm）",
    "Adjustment amounts": "调整量",
    ". The fastener parts per rail are on the workbook's Adjustment sheet.": "。各轨的扣件配件见工作簿的调整作业表。",
    "No rail to move: every check of the tolerance profile passes as measured.": "无需移动钢轨：实测即满足容许偏差标准的全部检测项。",
    "Work section {number} of {count}: {first} – {last}": "作业段 {number}/{count}：{first} – {last}",
    "{column} (a check no longer in tolerance profile {profile})": "{column}（容许偏差标准 {profile} 中已无此检测项）",
    "Repeatability": "重复性",
    "Repeatability of repeat runs": "重复测量的重复性",
    "Reference run {reference}, compared: {compared}; {count} valid sleepers of the reference compared by chainage "
    "(each run interpolated onto the reference stations, never across a gap of more than two sleepers). A run minus "
    "the reference carries the noise of both: the repeatability of one run is the pooled standard deviation / √2. A "
    "mean away from zero is a systematic shift between runs, not noise. Checks marked by magnitude (the differential "
    "versines) are compared by their absolute value: their worst value over the chord placements changes sign "
    "between runs wherever two placements of opposite sign nearly tie.":
        "参考测次 {reference}，比较：{compared}；按里程比较参考测次的 {count} 根有效轨枕（各测次内插到参考测次的里程，"
        "不跨越两根轨枕以上的缺口）。测次与参考之差含两者的噪声：单次测量的重复性为合并标准差 / √2。"
        "平均值偏离零为测次间的系统偏移而非噪声。标“按绝对值”的检测项（差分正矢）按绝对值比较："
        "在两个符号相反的弦位几乎相等处，其最不利值的符号会在测次间变化。",
    "Note: this comparison was made before the current results of this survey were written; run insrail compare "
    "again to bring it up to date.": "注意：此比较早于本次测量的当前结果；请重新运行 insrail compare 更新。",
    " (by magnitude)": "（按绝对值）",
    "runs": "测次",
    "mean (mm)": "平均值（mm）",
    "std (mm)": "标准差（mm）",
    "RMS (mm)": "中误差（mm）",
    "95 % |d| (mm)": "95 % |d|（mm）",
    "max |d| (mm)": "最大 |d|（mm）",
    "one run std (mm)": "单次标准差（mm）",
    "{name}: run minus reference": "{name}：测次减参考",
    "{project} - {survey}: track geometry survey report": "{project} - {survey}：轨道几何测量报告",
    "{project} - survey {survey} - {profile}": "{project} - 测量 {survey} - {profile}",
    "{software}; results {folder}": "{software}；结果 {folder}",
    "red: exceedances": "红色：超限",
    "max |{name}| ({unit})": "|{name}| 最大值（{unit}）",
    "fastener range exhausted": "扣件调整范围用尽",
    "conflicting checks": "检测项相互冲突",
    "check not held by the optimisation": "优化未计入此检测项",
    "none (ellipsoidal heights)": "无（大地高）",
    "auto": "自动",
    "constant": "常数",
    "plane": "平面",
    "quadratic": "二次曲面",
    # the desktop application's plots (insrail.project.plotdata)
    "Lateral deviation": "轨向偏差",
    "Vertical deviation": "高低偏差",
    "down": "地向",
    "up": "天向",
    "roll": "横滚",
    "pitch": "俯仰",
    "heading": "航向",
    "odometer": "里程计",
    "Position from the first epoch": "相对首历元的位置",
    "Position 1σ": "位置 1σ",
    "Velocity": "速度",
    "Attitude": "姿态",
    "Attitude 1σ": "姿态 1σ",
    "Gyro bias (estimated)": "陀螺零偏（估计值）",
    "Accelerometer bias (estimated)": "加速度计零偏（估计值）",
    "Gyro scale factor (estimated)": "陀螺比例因子（估计值）",
    "Accelerometer scale factor (estimated)": "加速度计比例因子（估计值）",
    "Odometer scale factor (estimated)": "里程计比例因子（估计值）",
    "GNSS minus fused antenna position": "GNSS 减融合后的天线位置",
    # a joined line section's page (insrail.report.section_page)
    "each sleeper takes the run with the better predicted accuracy": "每根轨枕取预测精度较好的测次",
    "each sleeper is the weighted mean of the runs (weights 1/sigma^2)": "每根轨枕取各测次的加权平均（权 1/sigma^2）",
    "Line section": "线路区段",
    "Line section: joined runs": "线路区段：拼接的测次",
    "Runs {runs}, joined on the stationing; in the overlaps {joined}. Sleepers are numbered continuously; the sleeper "
    "table's source columns say which run each row came from. Differential versines are compared by magnitude (the "
    "sign of their worst value over the chord placements flips where two placements tie) and not within a chord of "
    "an overlap's ends.": "测次 {runs} 按里程拼接；重叠段内{joined}。轨枕连续编号；轨枕表的来源列注明每行所属测次。"
                          "差分正矢按绝对值比较（两个弦位几乎相等处其最不利值的符号会翻转），且不在重叠段两端一个弦长以内比较。",
    "Overlap {later} - {earlier}: {start:.1f} to {end:.1f} m, {sleepers} sleepers":
        "重叠段 {later} - {earlier}：{start:.1f} 至 {end:.1f} m，轨枕 {sleepers} 根",
    "predicted sigma (mm)": "预测标准差（mm）",
    "> 3 sigma": "> 3 倍标准差",
    "The runs do not overlap.": "各测次无重叠。",
    # exports (insrail.export): the texts for people; the column names stay
    "design alignment {design}": "设计线形 {design}",
    "the line fitted to the measured centreline (no design alignment; thesis eq. 5.24)": "按实测中线拟合的线形（无设计线形；论文式 5.24）",
    "{columns}: {reference}, where the rail is (not an instruction)": "{columns}：{reference}，钢轨所在位置（非作业指令）",
    "mm; lift + up, lining + to the right looking towards increasing chainage; empty = not measured":
        "mm；面向里程增加方向：起道向上为正，拨道向右为正；空白 = 未测",
    "lining": "拨道",
    "lift": "起道",
    "normal heights": "正常高",
    "ellipsoidal heights": "大地高",
    "insrail: {project}, survey {survey}; {crs}; {heights}; m": "insrail：{project}，测量 {survey}；{crs}；{heights}；m",
    "deviations (not drawn): {reference}": "偏差量（未绘出）：{reference}",
    # relative surveys and the IMU mounting (insrail.report.content)
    "Survey kind": "测量类型",
    "relative survey: no GNSS, no prism fixes (IMU, odometer and stops); gauge, cant, twist and the chord checks are "
    "measured, coordinates and deviations from the design are not":
        "相对测量：无 GNSS、无棱镜定位（IMU、里程计与停车点）；测量轨距、超高、扭曲及弦测检测，不测坐标及与设计的偏差",
    "{survey} (relative survey)": "{survey}（相对测量）",
    "IMU mounting": "IMU 安装角",
    "yaw": "航向",
    "{axis} {estimate:+.3f}° ± {sigma:.3f}°": "{axis} {estimate:+.3f}° ± {sigma:.3f}°",
    " (applied)": "（已采用）",
    "{axis} not estimated ({reason})": "{axis} 未估计（{reason}）",
    "; ": "；",
    "processed with roll, pitch, yaw [{applied}]° (survey.toml [{given}]°); estimated from the survey: {estimates}":
        "解算采用横滚、俯仰、航向角 [{applied}]°（survey.toml 中为 [{given}]°）；由本次测量估计：{estimates}",
    "the NHC is off": "未启用非完整约束（NHC）",
    "no GNSS: only the NHC gives the direction of travel in the IMU's axes":
        "无 GNSS：仅非完整约束（NHC）给出 IMU 坐标系中的行进方向",
    "the pass without the NHC is not consistent": "不加非完整约束（NHC）的解算不自洽",
    "no design cant to compare the cant with": "无设计超高可供比较",
    "fused before the mounting calibration": "解算早于安装角标定",
    # the second odometer (insrail.report.content.odometer_pair_text)
    "Two odometers": "双里程计",
    "the right wheel counts {scale:+.2f} per mille against the left one (put on its scale)":
        "右轮计程相对左轮 {scale:+.2f}‰（已归算到左轮比例）",
    "the wheels disagree by {slip:.1f} % from {start:.1f} to {end:.1f} s ({low:.0f}-{high:.0f} m travelled): both left "
    "out there": "两轮计程相差 {slip:.1f}%（{start:.1f} 至 {end:.1f} s，行程 {low:.0f}-{high:.0f} m）：该段两轮均不采用",
    "{wheel} slipped {slip:.1f} % from {start:.1f} to {end:.1f} s ({low:.0f}-{high:.0f} m travelled): left out there, "
    "bridged by the other wheel": "{wheel}打滑 {slip:.1f}%（{start:.1f} 至 {end:.1f} s，行程 {low:.0f}-{high:.0f} m）：该段不采用，由另一轮衔接",
    "left wheel": "左轮",
    "right wheel": "右轮",
    "no slip found": "未发现打滑",
    # tamping re-design (insrail redesign): the PDF's section, the Tamping sheet, the template exports' notes
    "Tamping": "捣固",
    "Tamping re-design": "捣固重新设计",
    "Tamping sheet": "捣固作业表",
    "The least lift and slew per sleeper after which the track passes the chord checks of {profile} (each held "
    "{margin_mm:g} mm inside its limit): {direction}, lift {min_lift_mm:g} to {max_lift_mm:g} mm, slew at most "
    "{max_slew_mm:g} mm; largest lift {lift_mm:.1f} mm at {lift_at_m:.1f} m, largest slew {slew_mm:.1f} mm at "
    "{slew_at_m:.1f} m, {sleepers} sleepers moved; exceedances {before} before, {after} after the job. Signs: "
    "{convention}.":
        "每根轨枕处使线路通过 {profile} 各弦测检测（各留 {margin_mm:g} mm 余量）的最小起道量与拨道量：{direction}，"
        "起道 {min_lift_mm:g} 至 {max_lift_mm:g} mm，拨道不超过 {max_slew_mm:g} mm；最大起道 {lift_mm:.1f} mm，位于 "
        "{lift_at_m:.1f} m；最大拨道 {slew_mm:.1f} mm，位于 {slew_at_m:.1f} m；移动轨枕 {sleepers} 根；超限：作业前 "
        "{before} 处，作业后 {after} 处。符号：{convention}。",
    "lift only": "只起不落",
    "lift or lower": "可起可落",
    "Fixed stretches": "固定点区段",
    "tolerance (mm)": "允许偏差（mm）",
    "value (mm)": "数值（mm）",
    "none": "无",
    "Where a bound holds, and what cannot pass": "受限区段及无法通过的检测",
    "cannot pass: {what}": "无法通过：{what}",
    "lift at max_lift": "起道达到最大起道量",
    "slew at max_slew": "拨道达到最大拨道量",
    "lift at min_lift": "起道达到最小起道量",
    "fixed stretch": "固定点区段",
    "{channel}: before (measured) and after the job": "{channel}：作业前（实测）与作业后",
    "before": "作业前",
    "after": "作业后",
    "The tamping re-design, in working order (increasing chainage). ": "捣固重新设计，按作业顺序（里程增加方向）。",
    "{amounts}. Signs: {convention}.": "{amounts}。符号：{convention}。",
    "lift_left_mm, lift_right_mm, slew_mm: move the rail (the track) by the amount after which the track passes the "
    "profile's chord checks (docs/tamping.md); cant_mm = the cant after the job":
        "左轨起道、右轨起道、拨道：钢轨（线路）按此量移动后即通过容许偏差标准的各项弦测检测；作业后超高：作业完成后的超高",
    "mm; lift + up; slew + to the right looking towards increasing chainage; cant + left rail higher; mark: "
    "TS/SC/CS/ST, PVI of the re-designed line, fixed start/end":
        "mm；面向里程增加方向：起道向上为正，拨道向右为正；超高左轨高为正；标记：重新设计线形的直缓/缓圆/圆缓/缓直点、"
        "变坡点，固定点起点/终点",
    "station (m)": "测站里程（m）",
    "lift left (mm)": "左轨起道（mm）",
    "lift right (mm)": "右轨起道（mm）",
    "slew (mm)": "拨道（mm）",
    "cant after (mm)": "作业后超高（mm）",
    "mark": "标记",
    "Work section {number} of {count}: {first} – {last}, {rows} rows": "作业段 {number}/{count}：{first} – {last}，共 {rows} 行",
    "Marks of the re-designed line and the fixed stretches": "重新设计线形的特征点及固定点区段",
    "TS (tangent to spiral)": "直缓点",
    "SC (spiral to curve)": "缓圆点",
    "CS (curve to spiral)": "圆缓点",
    "ST (spiral to tangent)": "缓直点",
    "PC (tangent to curve)": "直圆点",
    "PT (curve to tangent)": "圆直点",
    "SS (spiral to spiral)": "缓和曲线连接点",
    "POT (tangent to tangent)": "直线连接点",
    "PVI (vertical intersection)": "变坡点",
    "fixed start ({source})": "固定点起点（{source}）",
    "fixed end ({source})": "固定点终点（{source}）",
    "{template}: tamping amounts of {project}, survey {survey} (insrail)": "{template}：{project} 捣固量，测量 {survey}（insrail）",
    "{sign} = rail up": "{sign} = 钢轨抬高",
    "{sign} = track to the right looking towards increasing chainage": "{sign} = 面向里程增加方向线路向右",
    "{sign} = left rail higher": "{sign} = 左轨较高",
    "station": "测站里程",
    "station (negated)": "测站里程（取负）",
    # the predicted accuracy (insrail.quality.tables): the Plan survey dialog's rows, verdicts and heading
    "absolute position, lateral": "绝对位置，横向",
    "absolute position, vertical": "绝对位置，垂向",
    "cant (1500 mm x roll)": "超高（1500 mm × 横滚角）",
    "30 m/5 m alignment (5 m lag)": "30 m 弦 5 m 检测轨向（5 m 间隔）",
    "30 m/5 m vertical (5 m lag)": "30 m 弦 5 m 检测高低（5 m 间隔）",
    "300 m/150 m alignment (150 m lag)": "300 m 弦 150 m 检测轨向（150 m 间隔）",
    "300 m/150 m vertical (150 m lag)": "300 m 弦 150 m 检测高低（150 m 间隔）",
    "outage: lateral sigma growth": "失锁：横向标准差增长",
    "outage: vertical sigma growth": "失锁：垂向标准差增长",
    "ok": "合格",
    "exceeds the limit at 3 sigma": "3 倍标准差超出限值",
    "relative survey (no GNSS, no prism: odometer, NHC and stops)": "相对测量（无 GNSS、无棱镜：里程计、非完整约束与停车点）",
    "Predicted accuracy, {solution} solution: IMU {imu}, {source}, {speed_mps:g} m/s, {length_m:g} m":
        "预测精度，{solution}解：IMU {imu}，{source}，{speed_mps:g} m/s，{length_m:g} m",
    "smoothed": "平滑",
    "forward": "前向",
    ", a {stop_s:g} s stop every {spacing_m:g} m": "，每 {spacing_m:g} m 停车 {stop_s:g} s",
    ", {duration_s:g} s outage at {station_m:g} m": "，{station_m:g} m 处失锁 {duration_s:g} s",
    # the event kinds' effect (insrail.io.events.EVENT_KINDS: the event dialog's tooltip)
    "not assessed unless the event names a tolerance profile for it": "不评估，除非该事件指定了其容许偏差标准",
    "marked": "仅标注",
    # ------------------------------------------------------------------ notices (insrail.notices: templates)
    "{stage}: {message}": "{stage}：{message}",
    # the stages
    "imu": "IMU",
    "fusion": "组合导航",
    "gnss": "GNSS",
    "heights": "高程",
    "track": "轨道",
    "survey": "测量",
    "time": "时间同步",
    "geodesy": "坐标基准",
    "gauge": "轨距",
    "cache": "缓存",
    "fuse": "组合导航",
    "total station": "全站仪",
    # the aiding sources, the states a filter reset widens, an IMU outlier's reasons and quantities
    "gnss_position": "GNSS 位置",
    "gnss_velocity": "GNSS 速度",
    "odometer_nhc": "里程计与非完整约束",
    "zupt": "零速修正（ZUPT）",
    "position_fix": "棱镜定位",
    "position": "位置",
    "velocity": "速度",
    "attitude": "姿态",
    "sensor errors": "传感器误差",
    "odometer scale": "里程计比例因子",
    "GNSS error": "GNSS 误差",
    "not finite": "非有限值",
    "beyond range": "超出量程",
    "spike": "尖峰",
    "spike below the envelope": "包络内尖峰",
    "specific force": "比力",
    "angular rate": "角速度",
    "GNSS": "GNSS",
    "GNSS positions": "GNSS 位置",
    "prism fixes": "棱镜定位点",
    "relative start": "相对测量起点",
    "the IMU": "IMU 处",
    "the odometer wheel's contact": "里程计轮的接触点",
    "a local frame": "局部坐标系",
    "a local frame on the central meridian": "中央子午线上的局部坐标系",
    "the design at station {station_m:.3f} m": "里程 {station_m:.3f} m 处的设计线形",
    "the whole survey": "整个测段",
    "stations {from_m:.1f} to {to_m:.1f} m": "里程 {from_m:.1f} 至 {to_m:.1f} m",
    "before its first": "在第一个之前",
    "beyond its last": "在最后一个之后",
    "{reasons}": "{reasons}",
    "{check} {direction}": "{check} {direction}",
    # the IMU
    "{source}IMU gap of {gap_s:.3f} s after t = {time_s:.4f} s: {missing} missing samples bridged by interpolation{aiding}":
        "{source}IMU 数据在 t = {time_s:.4f} s 之后中断 {gap_s:.3f} s：缺失的 {missing} 个采样已插值补齐{aiding}",
    "; across it the trajectory rests on the aiding (odometer, NHC, GNSS) and the interpolated motion":
        "；其间轨迹依靠辅助观测（里程计、NHC、GNSS）与插值的运动",
    "{where}IMU record {record} at t = {time_s:.4f} s removed as an outlier: {what}; bridged":
        "{where}IMU 第 {record} 条记录（t = {time_s:.4f} s）作为粗差剔除：{what}；已插值补齐",
    "{quantity} {axis} is {value}": "{quantity} {axis} 为 {value}",
    "{quantity} {axis} {value:.4g} {unit} against {reference:.4g} {unit} around it ({reason})":
        "{quantity} {axis} 为 {value:.4g} {unit}，其邻近为 {reference:.4g} {unit}（{reason}）",
    "{where}{count} of {records} IMU records depart from their neighbours by more than {sigmas:g} x their spread: the "
    "motion is too rough to tell a single faulty record inside the envelope from it; none removed by that test, and "
    "such a fault would be seen only by the aiding":
        "{where}{records} 条 IMU 记录中有 {count} 条偏离相邻记录超过其离散度的 {sigmas:g} 倍：运动过于剧烈，无法从中分辨包络内的"
        "单条错误记录；该检验未剔除任何记录，此类错误只能由辅助观测发现",
    "{where}{count} more IMU records removed as outliers between t = {first_s:.4f} and {last_s:.4f} s and bridged (all "
    "listed in the fusion log)":
        "{where}另有 {count} 条 IMU 记录在 t = {first_s:.4f} 至 {last_s:.4f} s 之间作为粗差剔除并插值补齐（均列于组合导航日志）",
    # the fusion
    "no odometer in the survey: the along-track scale comes from the {source} only": "测量无里程计：沿线方向的尺度仅来自{source}",
    "no trolley.imu_to_reference_rail_m (a survey not on rails): the non-holonomic constraint is applied at {where}":
        "未给出 trolley.imu_to_reference_rail_m（非轨道上的测量）：非完整约束施加于{where}",
    "no odometer: across the {source} outage of {outage_s:.0f} s after t = {time_s:.1f} s the along-track position rests "
    "on the IMU alone":
        "无里程计：t = {time_s:.1f} s 之后 {source} 中断 {outage_s:.0f} s，其间沿线位置仅依靠 IMU",
    "filter reset at t = {time_s:.1f} s: {source}{others} rejected for {rejected_s:.1f} s ({rejected} in a row){turned}; "
    "{states} uncertainty widened and the measurements re-admitted":
        "t = {time_s:.1f} s 滤波器重置：{source}{others}连续 {rejected_s:.1f} s 被拒（连续 {rejected} 次）{turned}；"
        "{states}的不确定度放大，观测重新接纳",
    " (and {sources})": "（及 {sources}）",
    "; heading re-aligned to the track by {turned_deg:+.1f} deg": "；航向按轨道重新对准 {turned_deg:+.1f}°",
    "{source} back after a gap of {gap_s:.1f} s at t = {time_s:.1f} s, {off} off the dead reckoning: the uncertainty "
    "grown over the gap to that ({instead}) and the gap bridged by the smoother":
        "{source}中断 {gap_s:.1f} s 后于 t = {time_s:.1f} s 恢复，与航位推算相差 {off}：中断期间的不确定度已相应放大"
        "（{instead}），中断由平滑器桥接",
    "instead of a filter reset": "代替滤波器重置",
    "accepted, but beyond the 1-sigma the filter held": "已接纳，但超出滤波器所持的 1σ",
    "not valid from t = {time_from_s:.1f} s to {time_to_s:.1f} s (travelled {station_from_m:.0f}-{station_to_m:.0f} m): "
    "{why}; its sleepers are not assessed":
        "t = {time_from_s:.1f} s 至 {time_to_s:.1f} s 无效（行程 {station_from_m:.0f}-{station_to_m:.0f} m）：{why}；"
        "其间轨枕不评估",
    "not valid from t = {time_from_s:.1f} s to {time_to_s:.1f} s: {why}; its sleepers are not assessed":
        "t = {time_from_s:.1f} s 至 {time_to_s:.1f} s 无效：{why}；其间轨枕不评估",
    "{source} {share_pct:.0f} % rejected": "{source} {share_pct:.0f} % 被拒",
    "{source} residuals {ratio:.1f} x their 1-sigma": "{source} 残差为其 1σ 的 {ratio:.1f} 倍",
    "the trajectory misses the {source} at t = {time_s:.1f} s by {off_m:.3f} m, {ratio:.0f} x its 1-sigma":
        "轨迹在 t = {time_s:.1f} s 偏离{source} {off_m:.3f} m，为其 1σ 的 {ratio:.0f} 倍",
    "trolley play estimated from the NHC innovations: {play} mm^2 per metre run lateral/vertical (the profile "
    "resources/trolley_play.toml: {profile_play}), NHC 1-sigma {nhc_sigma_mmps:.3g} mm/s; the stated accuracy uses them":
        "由 NHC 新息估计小车晃动：横向/垂向每米行程 {play} mm²（配置 resources/trolley_play.toml：{profile_play}），"
        "NHC 1σ {nhc_sigma_mmps:.3g} mm/s；所述精度采用这些值",
    "the non-holonomic constraint does not hold: {share_pct:.0f} % of its {rows} rows rejected, with no odometer to blame "
    "(a hand-held device, or a vehicle that slides); fused again without it (insrail fuse --no-nhc does so from the "
    "start)":
        "非完整约束不成立：{rows} 行中 {share_pct:.0f} % 被拒，且无里程计可归咎（手持设备或打滑的车辆）；已不用该约束重新组合"
        "（insrail fuse --no-nhc 从一开始即如此）",
    "the GNSS positions disagree with their stated sigmas: {share_pct:.0f} % of {fixes} fixes rejected, NIS {nis:.2f} x "
    "its degrees of freedom (median {median_nis:.2f}); fused again with the file's sigmas x {scale:.2f} (calibrated "
    "from the innovations; --gnss-sigma-scale sets a factor from the start)":
        "GNSS 位置与其标称 σ 不符：{fixes} 个定位点中 {share_pct:.0f} % 被拒，NIS 为其自由度的 {nis:.2f} 倍（中位数 "
        "{median_nis:.2f}）；已按文件 σ 乘以 {scale:.2f} 重新组合（由新息标定；--gnss-sigma-scale 可从一开始给定系数）",
    # the start of the fusion
    "{source} track's chord": "{source}轨迹的弦",
    "{source} track of the first motion": "{source}首次运动的轨迹",
    "the design's azimuth at the start (station {station_m:.1f} m, {offset_m:+.2f} m off it) is {apart_deg:.2f} deg "
    "from the {what}, more than 3 x their 1-sigma ({limit_deg:.2f} deg): not used for the start":
        "起点处的设计方位角（里程 {station_m:.1f} m，偏离 {offset_m:+.2f} m）与{what}相差 {apart_deg:.2f}°，超过其 1σ 的 3 倍"
        "（{limit_deg:.2f}°）：不用于起始对准",
    "moving start: initial attitude by matching the IMU to the {source} velocities over {window_s:.0f} s, heading "
    "{heading_deg:.2f} deg (1-sigma {sigma_deg:.2f} deg)":
        "动态起始：将 IMU 与{source}速度在 {window_s:.0f} s 内匹配得到初始姿态，航向 {heading_deg:.2f}°（1σ {sigma_deg:.2f}°）",
    "the design's azimuth at station {station_m:.1f} m, the direction from the {source} track":
        "里程 {station_m:.1f} m 处的设计方位角，方向取自{source}轨迹",
    "the {source} track over {chord_m:g} m chords": "{source}轨迹的 {chord_m:g} m 弦",
    "moving start: initial heading {heading_deg:.2f} deg from {where} (1-sigma {sigma_deg:.2f} deg)":
        "动态起始：初始航向 {heading_deg:.2f}°，取自{where}（1σ {sigma_deg:.2f}°）",
    "a {profile} gyro does not resolve the earth rate": "{profile} 陀螺分辨不出地球自转角速度",
    "gyrocompass 1-sigma {sigma_deg:.1f} deg with the {profile} profile": "以 {profile} 配置陀螺寻北的 1σ 为 {sigma_deg:.1f}°",
    "the design's azimuth at station {station_m:.1f} m, the direction from the {source} track of the first motion":
        "里程 {station_m:.1f} m 处的设计方位角，方向取自{source}首次运动的轨迹",
    "the {source} track of the first motion over {chord_m:g} m chords": "{source}首次运动轨迹的 {chord_m:g} m 弦",
    "static start: heading {heading_deg:.2f} deg from {where} (1-sigma {sigma_deg:.2f} deg), not by gyrocompassing "
    "({reason}){backwards}":
        "静态起始：航向 {heading_deg:.2f}°，取自{where}（1σ {sigma_deg:.2f}°），未采用陀螺寻北（{reason}）{backwards}",
    "; the trolley set off backwards": "；小车倒向出发",
    # a relative survey's start
    "relative survey in a local frame: latitude {lat_deg:.2f} deg from the earth rate at the static start (1-sigma "
    "{sigma_deg:.2f} deg)":
        "局部坐标系中的相对测量：纬度 {lat_deg:.2f}°，由静态起始时的地球自转角速度求得（1σ {sigma_deg:.2f}°）",
    "relative survey: heading {heading_deg:.2f} deg by gyrocompassing (1-sigma {sigma_deg:.3f} deg: the frame's azimuth)":
        "相对测量：陀螺寻北得航向 {heading_deg:.2f}°（1σ {sigma_deg:.3f}°：坐标系的方位角）",
    "towards increasing stationing (taken: the gyros do not tell)": "朝里程增加方向（假定：陀螺无法判别）",
    "towards increasing stationing (coarse gyrocompass)": "朝里程增加方向（粗略陀螺寻北）",
    "against increasing stationing (coarse gyrocompass)": "朝里程减小方向（粗略陀螺寻北）",
    "relative survey: heading {heading_deg:.2f} deg from {frame} (1-sigma {sigma_deg:.2f} deg: the frame's azimuth), "
    "the trolley running {direction}":
        "相对测量：航向 {heading_deg:.2f}°，取自{frame}（1σ {sigma_deg:.2f}°：坐标系的方位角），小车{direction}运行",
    "relative survey (no GNSS, no prism fixes): the trajectory starts on {frame}; gauge, cant, twist and the chord "
    "checks are measured, coordinates and deviations from the design are not":
        "相对测量（无 GNSS、无棱镜定位）：轨迹起始于{frame}；测量轨距、超高、扭曲及弦测检查，不测量坐标及相对设计的偏差",
    # the IMU mounting
    "IMU mounting from the survey: {axes}": "由测量数据估计的 IMU 安装角：{axes}",
    "{axis} {estimate_deg:+.3f} deg (1-sigma {sigma_deg:.4f}, given {given_deg:+.3f})":
        "{axis} {estimate_deg:+.3f}°（1σ {sigma_deg:.4f}，给定 {given_deg:+.3f}）",
    "{axis} by {apart_deg:.3f} deg ({sigmas:.0f} sigma)": "{axis} 相差 {apart_deg:.3f}°（{sigmas:.0f} σ）",
    "the IMU mounting the survey shows differs from {source}'s trolley.mounting_rpy_deg by more than {sigmas:g} sigma "
    "({apart}): the survey is processed with the estimate; give trolley.mounting_rpy_deg = [{values}]{roll}":
        "测量数据显示的 IMU 安装角与 {source} 的 trolley.mounting_rpy_deg 相差超过 {sigmas:g} σ（{apart}）：本次测量按估计值"
        "处理；请给出 trolley.mounting_rpy_deg = [{values}]{roll}",
    " (the roll takes the track's mean cross-level for the design's)": "（横滚以轨道的平均水平作为设计值）",
    # the pipeline's checks of the input
    "files.{role}: {entry} lies outside the project and the survey folder ({path}): check that it is the file meant":
        "files.{role}：{entry} 位于项目及测量文件夹之外（{path}）：请确认是所需文件",
    "the cached {stage} {file} was damaged ({reason}): recomputed": "缓存的 {stage} {file} 已损坏（{reason}）：已重新计算",
    "it has no checksum (a run stopped while writing it, or an older insrail wrote it)":
        "缺少校验和（写入时运行中断，或由旧版 insrail 写入）",
    "it is empty": "文件为空",
    "its contents do not match its checksum (truncated or altered)": "内容与校验和不符（被截断或被修改）",
    "the CRS is on {ellipsoid}: GNSS positions are taken in its datum; a GNSS solution computed with WGS84's formulas "
    "from a base given in that datum reads baselines {scale_ppm:+.1f} ppm long ({at_5km_mm:+.0f} mm at 5 km from the "
    "base): lengths and chainage read that much long, absolute positions need common points ([geodesy.local]) or a "
    "solution made on this ellipsoid":
        "坐标系基于 {ellipsoid}：GNSS 位置按该基准取用；用 WGS84 公式、由该基准下给出的基站解算的 GNSS 结果，基线偏长 "
        "{scale_ppm:+.1f} ppm（距基站 5 km 处 {at_5km_mm:+.0f} mm）：长度与里程相应偏长，绝对位置需要公共点"
        "（[geodesy.local]）或在该椭球上解算的结果",
    "{label}: {count} gauge reading(s) more than {offset_mm:.0f} mm from the median {median_mm:.1f} mm removed as "
    "outliers ({listed}{more})":
        "{label}：{count} 个轨距读数偏离中位数 {median_mm:.1f} mm 超过 {offset_mm:.0f} mm，作为粗差剔除（{listed}{more}）",
    " and {more} more": "，另有 {more} 个",
    "{sleepers}: the sleeper pulses lie {scatter_pct:.1f} % (RMS) off whole sleeper spacings along the odometer "
    "({odometer}), more than sleepers are laid to: a file of another run, or a detector that misses, doubles or "
    "delays pulses":
        "{sleepers}：轨枕脉冲沿里程计（{odometer}）偏离整数轨枕间距 {scatter_pct:.1f} %（RMS），超过轨枕铺设的精度："
        "可能是另一次测量的文件，或检测器漏计、重计或延迟脉冲",
    "its time stamps run {seconds:.2f} s late against the IMU's clock (±{sigma_s:.2f} s, from {method}{given})":
        "其时间标记比 IMU 时钟晚 {seconds:.2f} s（±{sigma_s:.2f} s，由{method}求得{given}）",
    "its time stamps run {seconds:.2f} s early against the IMU's clock (±{sigma_s:.2f} s, from {method}{given})":
        "其时间标记比 IMU 时钟早 {seconds:.2f} s（±{sigma_s:.2f} s，由{method}求得{given}）",
    "; after the time_offset_s = {given_s:g} s given": "；已计入给定的 time_offset_s = {given_s:g} s",
    "{label}: {text}: check the time synchronisation, or give the offset as time_offset_s = {offset_s:.2f} in "
    "[files.{role}] of survey.toml if it is the sensor's latency":
        "{label}：{text}：请检查时间同步；若为传感器的延迟，请在 survey.toml 的 [files.{role}] 中给出 time_offset_s = "
        "{offset_s:.2f}",
    "its acceleration against the IMU's, r = {r:.3f}": "其加速度与 IMU 加速度的相关（r = {r:.3f}）",
    "its speed against the odometer's, r = {r:.3f}{added}": "其速度与里程计速度的相关（r = {r:.3f}）{added}",
    "the spacing of its pulses along the odometer{added}": "其脉冲沿里程计的间距{added}",
    ", the odometer's offset against the IMU added": "，并加上里程计相对 IMU 的时差",
    "the odometer's and the GNSS's accelerations and speeds, which agree": "里程计与 GNSS 一致的加速度和速度",
    # heights, the GNSS solution, control
    "height anomaly extrapolated at {count} of {total} points: chainage {from_m:.1f} to {to_m:.1f} m is outside the "
    "benchmarks' span {lo_m:.1f} to {hi_m:.1f} m (up to {beyond_m:.1f} m beyond)":
        "{total} 个点中 {count} 个的高程异常为外推：里程 {from_m:.1f} 至 {to_m:.1f} m 超出水准点范围 {lo_m:.1f} 至 {hi_m:.1f} m"
        "（最远超出 {beyond_m:.1f} m）",
    "height anomaly extrapolated at {count} of {total} points: the benchmarks have no 2-D hull (collinear), so every "
    "point off their line is extrapolated":
        "{total} 个点中 {count} 个的高程异常为外推：水准点共线，无二维凸包，偏离其连线的点均为外推",
    "height anomaly extrapolated at {count} of {total} points: they lie outside the benchmarks' convex hull, up to "
    "{beyond_m:.1f} m beyond it":
        "{total} 个点中 {count} 个的高程异常为外推：这些点位于水准点凸包之外，最远超出 {beyond_m:.1f} m",
    "control point {point}: {warning}": "控制点 {point}：{warning}",
    "base position from the RTKLIB options: ant2-postype = {postype}": "基站位置取自 RTKLIB 选项：ant2-postype = {postype}",
    "base position from the RINEX header of {file} (APPROX POSITION XYZ {xyz}): approximate, metre level; every rover "
    "position carries its error. Give the control point's coordinates for survey work.":
        "基站位置取自 {file} 的 RINEX 文件头（APPROX POSITION XYZ {xyz}）：为米级近似值，每个流动站位置都带有该误差。"
        "测量作业请给出控制点坐标。",
    "baseline {baseline_km:.1f} km is longer than the {short_km:.0f} km of short-baseline PPK: expect slower fixing and "
    "larger errors; use a nearer base":
        "基线 {baseline_km:.1f} km 超过短基线 PPK 的 {short_km:.0f} km：固定将更慢、误差更大；请使用更近的基站",
    "local control point {point}: the other points predict it {off_mm:.1f} mm off (leave-one-out; E/N/H {enh} mm): "
    "check its coordinates in [geodesy.local.points]":
        "局部控制点 {point}：其余各点推算其偏差 {off_mm:.1f} mm（留一法；E/N/H {enh} mm）：请检查其在 "
        "[geodesy.local.points] 中的坐标",
    "set-up {setup} (line {line}): CPIII point {point} does not fit (leave-one-out residual {plan_mm:.1f} mm in plan, "
    "{height_mm:.1f} mm in height, {ratio:.1f} times the limit of the test against its 1-sigma): left out; check its "
    "coordinates":
        "设站 {setup}（第 {line} 行）：CPIII 点 {point} 不符（留一法残差平面 {plan_mm:.1f} mm、高程 {height_mm:.1f} mm，"
        "为按其 1σ 检验限值的 {ratio:.1f} 倍）：已剔除；请检查其坐标",
    "the run goes on {run_m:.0f} m {where} prism fix (at {time_s:.1f} s) with no GNSS: the sleepers there rest on the "
    "INS and the odometer alone, their position 1-sigma growing with the distance (sleepers.csv, quality.csv); start "
    "and end a survey without GNSS on a fix":
        "测量在无 GNSS 的情况下于棱镜定位点（{time_s:.1f} s）{where}继续行进 {run_m:.0f} m：该段轨枕仅依靠惯导与里程计，"
        "其位置 1σ 随距离增大（sleepers.csv、quality.csv）；无 GNSS 的测量应在定位点上开始和结束",
    "{count} total-station prism fix(es) placed by project {project} ({crs})":
        "由项目 {project}（{crs}）放置了 {count} 个全站仪棱镜定位点",
    # the track
    "{checks} not checked at {count} sleepers between {from_m:.1f} m and {to_m:.1f} m: {what}":
        "{checks} 在 {from_m:.1f} m 至 {to_m:.1f} m 之间的 {count} 根轨枕处未检查：{what}",
    "no line speed ([track] line_speed_kmh in project.toml)": "无线路速度（project.toml 的 [track] line_speed_kmh）",
    "no curvature (no design alignment and no fitted line there)": "无曲率（该处无设计线形，也无拟合线形）",
    "no line-type fit over {where} (no fitted alignment, no deviations \"measured - best\"): {error}":
        "{where}无线形拟合（无拟合线形，无“实测 − 最优”偏差）：{error}",
    "{check}: not assessable at the stated 1-sigma {sigma_mm:.2f} mm (quality.csv) against its limit {limit_mm:.1f} mm "
    "({sigmas:g} sigma beyond it: the survey's noise alone would cross it) over {where}: {sleepers} sleepers not assessed for it, {exceedances} "
    "exceedances there not listed; a better IMU, slower pushing or more control makes it assessable":
        "{check}：在 {where} 所述 1σ {sigma_mm:.2f} mm（quality.csv）相对其限值 {limit_mm:.1f} mm 不可评估（其 {sigmas:g} 倍"
        "超出限值：仅测量噪声即可超限）：{sleepers} 根轨枕未就此评估，该处 {exceedances} 处超限未列出；更好的 IMU、更慢的推行速度或更多控制点可使其"
        "可评估",
    "relative survey: the {check} check cannot be assessed in {count} of {sections} sections, where the stated 1-sigma "
    "of its error exceeds 1/{sigmas:g} of its {limit_mm:g} mm limit: {where}; its values and exceedances "
    "there are left out":
        "相对测量：{check} 检查在 {sections} 个区段中的 {count} 个不可评估，这些区段所述误差 1σ 超过其 {limit_mm:g} mm 限值的 "
        "1/{sigmas:g}：{where}；这些区段的数值与超限均不列出",
    "{from_m:.0f}-{to_m:.0f} m ({sigma_mm:.2f} mm)": "{from_m:.0f}-{to_m:.0f} m（{sigma_mm:.2f} mm）",
    "{from_m:.0f}-{to_m:.0f} m (too short for its lag)": "{from_m:.0f}-{to_m:.0f} m（短于其滞后距离）",
    "runs {runs} differ by {rms_mm:.2f} mm RMS in {parameter} over their overlap ({from_m:.0f}-{to_m:.0f} m), more than "
    "{sigmas:g} x the predicted {predicted_mm:.2f} mm":
        "测次 {runs} 在重叠段（{from_m:.0f}-{to_m:.0f} m）的 {parameter} 相差 {rms_mm:.2f} mm RMS，超过预计 "
        "{predicted_mm:.2f} mm 的 {sigmas:g} 倍",
    # the parameters a survey plan sweeps (insrail.names.QUANTITY_NAMES)
    "Gyro bias": "陀螺零偏",
    "Accelerometer bias": "加速度计零偏",
    "Gyro angle random walk": "陀螺角度随机游走",
    "Accelerometer velocity random walk": "加速度计速度随机游走",
    "GNSS position 1σ": "GNSS 定位 1σ",
    "Pushing speed": "推行速度",
    # how a GNSS base's coordinates were found (insrail.project.control_points, the PPK view)
    "geodetic coordinates from the project": "项目中的大地坐标",
    "engineering E/N through the CRS; h = H + zeta = {normal_m:.4f} m {zeta_m:+.4f} m (height anomaly model {model})":
        "工程坐标 E/N 经坐标系换算；h = H + ζ = {normal_m:.4f} m {zeta_m:+.4f} m（高程异常模型 {model}）",
    "engineering E/N through the CRS; no benchmarks in the project: H taken as ellipsoidal":
        "工程坐标 E/N 经坐标系换算；项目无水准点：H 作为椭球高",
    "APPROX POSITION XYZ of {file}: metre level": "{file} 的 APPROX POSITION XYZ：米级",
    # the fusion's integrity (summary.toml [fusion.integrity] summary)
    "{consistent} of {sections} sections of {section_m:.0f} m consistent with their 1-sigma{bad}{resets}{missed}"
    "{inconsistent}": "{sections} 个 {section_m:.0f} m 区段中 {consistent} 个与其 1σ 一致{bad}{resets}{missed}{inconsistent}",
    "; not valid: {share_pct:.0f} % of the length": "；无效：占长度的 {share_pct:.0f} %",
    "; {count} filter reset(s)": "；滤波器重置 {count} 次",
    "; {count} position fix(es) missed by the trajectory beyond their 1-sigma ({share_pct:.0f} % of the length)":
        "；轨迹偏离 {count} 个定位点超过其 1σ（占长度的 {share_pct:.0f} %）",
    # a start on the design (survey.toml [start])
    "1-sigma {sigma_m:.3f} m": "1σ {sigma_m:.3f} m",
    "1-sigma {sigma_m:.3f} m horizontal, {vertical_m:g} m in height": "平面 1σ {sigma_m:.3f} m，高程 {vertical_m:g} m",
    "as given": "按给定值",
    "by gyrocompassing": "由陀螺寻北",
    "from {source}": "取自{source}",
    "static start on {source}: position from the design ({sigmas}), heading {heading_deg:.2f} deg {how} (1-sigma "
    "{sigma_deg:.2f} deg)":
        "于{source}静态起始：位置取自设计（{sigmas}），航向 {heading_deg:.2f}° {how}（1σ {sigma_deg:.2f}°）",
    "moving start on {source}: position and attitude from the design ({sigmas}, {level_deg:.2f} deg level, "
    "{heading_deg:.2f} deg heading), speed {speed_mps:+.2f} m/s from the odometer":
        "于{source}动态起始：位置与姿态取自设计（{sigmas}，水平角 {level_deg:.2f}°，航向 {heading_deg:.2f}°），"
        "速度 {speed_mps:+.2f} m/s 取自里程计",
    "the design at station {station_m:.3f} m{offset}{height}{facing}": "设计线形里程 {station_m:.3f} m 处{offset}{height}{facing}",
    ", {offset_m:+.3f} m right": "，右偏 {offset_m:+.3f} m",
    ", {height_m:+.3f} m above": "，高出 {height_m:+.3f} m",
    ", facing decreasing stations": "，面向里程减小方向",
    "relative survey started on {frame}: {why}": "相对测量起始于{frame}：{why}",
    "the trajectory starts on the design with a 1-sigma of {start_mm:.0f} mm and reaches {end_mm:.0f} mm at "
    "{length_m:.0f} m from the azimuth's alone (the IMU's drift on top), so no deviation from the design nor any "
    "adjustment amount is given":
        "轨迹起始于设计线形，1σ 为 {start_mm:.0f} mm，仅方位角误差即使其在 {length_m:.0f} m 处达到 {end_mm:.0f} mm"
        "（另加 IMU 漂移），故不给出相对设计的偏差，也不给出任何调整量",
    # noise estimated from the innovations (self-calibration)
    "{source} noise estimated from its innovations: {sigma:.3g} {unit} (1-sigma, RMS), {given} {profile_sigma:.3g} "
    "{unit}; fused with {given} x {applied:.2f}, the stated accuracy uses it":
        "{source}噪声由其新息估计：{sigma:.3g} {unit}（1σ，均方根），{given} {profile_sigma:.3g} {unit}；"
        "融合时采用{given} × {applied:.2f}，所述精度已采用",
    "the file's": "文件给定值",
    "the profile's": "配置给定值",
    "GNSS {quality}": "GNSS {quality}",
    "ZUPT": "零速修正",
    # a relative survey's summary.toml [relative] (the processing log says them)
    "gauge, cant, twist and the chord checks (versines, short and long wave where assessed)":
        "轨距、超高、扭曲及弦测检查（正矢，可评估处的短波与长波不平顺）",
    "coordinates on the line and deviations from the design (the sleeper table's deviation columns are empty; its rail "
    "coordinates are in the survey's own frame, which drifts with the IMU)":
        "线路坐标及相对设计的偏差（轨枕表的偏差列为空；其钢轨坐标位于测量自身的坐标系中，随 IMU 漂移）",
    "{first} and {second}": "{first} 与 {second}",
    "nothing absolute: {why}": "不给出任何绝对量：{why}",
    # progress of the processing (the GUI's log and status bar; insrail.progress)
    "writing": "正在写入",
    "checking the input files": "正在检查输入文件",
    "RTKLIB post-processing": "RTKLIB 后处理",
    "reading the solution": "正在读取解算结果",
    "fix rate {fix_rate_pct:.1f} %": "固定率 {fix_rate_pct:.1f} %",
    "survey loaded": "测量数据已读入",
    "reading {role}: {file}": "正在读取 {role}：{file}",
    "fusion done": "组合导航解算完成",
    "forward filter {elapsed_s:.0f} s": "前向滤波 {elapsed_s:.0f} s",
    "smoother": "平滑",
    "trajectory": "轨迹",
    "strapdown: {done} of {epochs} IMU epochs": "捷联解算：IMU 历元 {done}/{epochs}",
    "IMU {done}/{epochs} epochs": "IMU 历元 {done}/{epochs}",
    "comparing": "正在比较",
    "done": "完成",
    "reading the results of {survey}": "正在读取测量 {survey} 的结果",
    "GNSS solution reused from the cache": "GNSS 解算结果取自缓存",
    "GNSS: preparing the observations": "GNSS：正在准备观测数据",
    "GNSS solution ready": "GNSS 解算完成",
    "fusion reused from the cache": "组合导航结果取自缓存",
    "height model": "高程模型",
    "rails, chainage and sleepers": "钢轨、里程与轨枕",
    "irregularities and exceedances": "不平顺与超限",
    "writing results": "正在写入结果",
    "reading the results": "正在读取结果",
    "fitting the line types to the track after the job": "按作业后线路拟合线形",
    "writing the re-design": "正在写入重新设计",
    "overlaps": "重叠段",
    "assessment on the joined table": "对合并后的轨枕表进行评定",
    "writing the section's results": "正在写入区段结果",
    "covariance: forward filter": "协方差：前向滤波",
    "covariance: smoother": "协方差：平滑",
    "covariance analysis done": "协方差分析完成",
    "{parameter} = {value:g} {unit}": "{parameter} = {value:g} {unit}",
    "sweep done": "参数扫描完成",
    "writing the table": "正在写入表格",
    "adjustment sheet": "调整量表",
    "tamping sheet": "捣固作业表",
    "materials list": "材料清单",
    "exceedance sheet": "超限表",
    "summary: parameters": "汇总：参数",
    "summary sheet": "汇总表",
    "processing log": "处理日志",
    "saving the workbook": "正在保存工作簿",
    "workbook written: {file}": "工作簿已写入：{file}",
    "the trajectory's statistics": "轨迹统计",
    "laying out the pages": "正在排版",
    "charts {station_m:.0f} m": "图表 {station_m:.0f} m",
    "report written: {file}": "报告已写入：{file}",
    "building the track": "正在生成线路",
    "odometer, gauge, sleepers": "里程计、轨距、轨枕",
    "writing files": "正在写入文件",
    "action threshold": "作业阈值",
    "adjustment amounts": "调整量",
    "tamping re-design: the lifts": "捣固重新设计：起道量",
    "tamping re-design: the slews": "捣固重新设计：拨道量",
    "tamping re-design: the track after the job": "捣固重新设计：作业后线路",
    "writing {file}": "正在写入 {file}",
    "{survey}: {message}": "{survey}：{message}",
    "{survey}: done in {elapsed_s:.1f} s": "{survey}：用时 {elapsed_s:.1f} s 完成",
    "{survey}: FAILED: {error}": "{survey}：失败：{error}",
    "waiting for {holder} to finish ({file})": "正在等待 {holder} 结束（{file}）",
    # why an axis of the IMU's mounting is not estimated from the survey (insrail.nav.mounting)
    "the trolley hardly moves": "小车几乎未移动",
    "fewer than {count} valid sleepers with a design cant": "具有设计超高的有效轨枕少于 {count} 根",
    "it needs the cant against a design's: insrail process": "需与设计超高比较：请运行 insrail process",
    "from the velocity": "由速度估计",
    "the pass without the NHC failed: {error}": "不加非完整约束（NHC）的解算失败：{error}",
    # why a sleeper is not assessed (sleepers.csv's not_assessed, said in the report's language)
    "fusion: {reason}": "组合导航：{reason}",
    "IMU gap of {gap_s:.2f} s bridged": "已桥接 {gap_s:.2f} s 的 IMU 数据中断",
    "{kind} {text}": "{kind} {text}",
    "{text}": "{text}",
    "{event} (assessed with {profile})": "{event}（按 {profile} 评定）",
    # what the project now says differently from the settings a survey was processed with (insrail.project.run_settings)
    "{what}: processed with {old}; the project now says {new}: process again":
        "{what}：处理时为 {old}；项目现为 {new}：请重新处理",
    "the project's settings cannot be resolved now ({error}): the results stand as recorded":
        "项目设置当前无法解析（{error}）：结果按记录保留",
    "coordinate system": "坐标系",
    "tolerance profile": "容许偏差标准",
    "fastener type": "扣件类型",
    "trolley geometry": "小车几何参数",
    "fusion options": "组合导航选项",
    "adjustment settings": "调整量设置",
    "{model} on {benchmarks}": "{model}（基于 {benchmarks}）",
    "ellipsoidal heights (no benchmarks)": "椭球高（无水准点）",
    "none (fitted lines)": "无（拟合线形）",
    "[{section}] of summary.toml": "summary.toml 的 [{section}]",
    "other values": "其他数值",
    "{setting} with other contents": "{setting}（内容已改变）",
}
