"""Simplified Chinese (zh-CN) of every text the reports, the exports and the display-name tables print.

English wording (as written in the code, the key) -> Chinese; :func:`insrail.names.t` looks it up. The field's
standard terms, as the thesis (Chen 2016, Figure 5-7) and TB 10754-2018 use them: 轨距 gauge, 水平 cross level,
超高 cant, 轨向 alignment, 高低 longitudinal level, 扭曲 (三角坑) twist, 轨距变化率 gauge change rate, 30 m 弦 5 m
检测 the 30 m / 5 m check (短波不平顺), 300 m 弦 150 m 检测 (长波不平顺), 正矢 versine, 调整量 adjustment amount,
里程 chainage, 轨枕 sleeper, 超限 exceedance, 偏差 deviation (实测 − 设计/最优). A template keeps its
English fields ({count}, {chord_m:g}); ``tests/test_languages.py`` checks that and that no text lacks its entry.
"""

ZH_CN: dict[str, str] = {
    # ------------------------------------------------------------------ readers' errors (insrail.io.errors.InputError)
    "{file}: {message}": "{file}：{message}",
    "{file}, line {line}: {message}": "{file}，第 {line} 行：{message}",
    "{file}, row {line}: {message}": "{file}，第 {line} 行（记录）：{message}",
    "{file}, index {line}: {message}": "{file}，第 {line} 条记录：{message}",
    "1 problem:": "1 个问题：",
    "{count} problems:": "{count} 个问题：",
    "{key}: {message}": "{key}：{message}",
    "{element_path}: {message}": "{element_path}：{message}",
    "file not found": "找不到文件",
    "cannot read the lift/lining table: {error}": "无法读取起道/拨道量表：{error}",
    "a version 1 table (amounts = -deviation, from an insrail before the amounts were the planned adjustment): export it again":
        "第 1 版的表（调整量 = −偏差，由调整量尚为计划调整量之前的 insrail 写出）：请重新导出",
    "expected the first line {magic!r}": "首行应为 {magic!r}",
    "expected a comment line '# key = value'": "应为注释行“# key = value”",
    "expected the header {header}": "表头应为 {header}",
    "expected {count} fields ({header}), found {found}": "应有 {count} 个字段（{header}），实有 {found} 个",
    "valid: expected 0 or 1, found {valid!r}": "valid：应为 0 或 1，实为 {valid!r}",
    "expected a whole sleeper number and numbers (or empty cells) after the chainage": "里程之后应为整数轨枕号及数值（或空单元格）",
    "no lift/lining table: {summary}": "无起道/拨道量表：{summary}",
    "template not found": "找不到模板",
    "not valid TOML: {error}": "不是有效的 TOML：{error}",
    "columns: expected [[columns]] entries with field (and title, unit, sign)": "columns：应为含 field（及 title、unit、sign）的 [[columns]] 条目",
    "columns[{i}].field: expected one of {known}, found {field!r}": "columns[{i}].field：应为 {known} 之一，实为 {field!r}",
    "columns[{i}].unit: expected {allowed} for {field}, found {unit!r}": "columns[{i}].unit：{field} 的单位应为 {allowed}，实为 {unit!r}",
    "columns[{i}].sign: expected 1 or -1 (numbers only), found {sign!r}": "columns[{i}].sign：应为 1 或 -1（仅限数字），实为 {sign!r}",
    "comment: expected the prefix of the lines that state the sign conventions": "comment：应为说明符号约定的各行的前缀",
    "spacing_m: expected 0 (every row) or a positive distance, found {spacing!r}": "spacing_m：应为 0（每行）或正的距离，实为 {spacing!r}",
    "decimals: expected 0 to 4, found {decimals!r}": "decimals：应为 0 至 4，实为 {decimals!r}",
    "not found: re-design the survey first (insrail redesign)": "不存在：请先对该测量进行重新设计（insrail redesign）",
    "expected '# insrail tamping 1' (a tamping.csv of insrail redesign)": "应为“# insrail tamping 1”（insrail redesign 写出的 tamping.csv）",
    "expected 7 fields, found {count}": "应有 7 个字段，实有 {count} 个",
    "expected numbers in station_m and the amounts": "station_m 及各调整量应为数值",
    "no rows": "没有数据行",
    "cannot tell the receiver format from the extension {suffix!r}: give the format, one of {receiver_formats}":
        "无法由扩展名 {suffix!r} 判断接收机格式：请指定格式，{receiver_formats} 之一",
    "output folder does not exist": "输出文件夹不存在",
    "unknown receiver format {format!r}: expected one of {receiver_formats}": "未知的接收机格式 {format!r}：应为 {receiver_formats} 之一",
    "unreadable receiver log: RTKLIB decoded no observations as {name} (check the format)":
        "无法读取接收机记录：RTKLIB 按 {name} 未解码出任何观测值（请检查格式）",
    "RTKLIB configuration file not found": "找不到 RTKLIB 配置文件",
    "expected 'key = value', found {line!r}": "应为“key = value”，实为 {line!r}",
    "no navigation data: give at least one RINEX navigation file": "无导航数据：请至少给出一个 RINEX 导航文件",
    "base and rover do not overlap in time: base {base_span}, rover {file} {rover_span}": "基准站与流动站在时间上不重叠：基准站 {base_span}，流动站 {file} {rover_span}",
    "output folder {parent} does not exist": "输出文件夹 {parent} 不存在",
    "RTKLIB produced no usable solution (check the navigation files, the time span and the options): {message}":
        "RTKLIB 未得出可用的解（请检查导航文件、时间段及选项）：{message}",
    "unknown base position: the RINEX header has no APPROX POSITION XYZ; give the base position (control point coordinates)":
        "基准站位置未知：RINEX 文件头中没有 APPROX POSITION XYZ；请给出基准站位置（控制点坐标）",
    "no observation epochs after the header": "文件头之后没有观测历元",
    "expected a RINEX navigation file (type N, G, ...), found type {file_type!r}": "应为 RINEX 导航文件（类型 N、G 等），实为类型 {file_type!r}",
    "no navigation data: the file holds a header and no ephemerides": "无导航数据：文件只有文件头，没有星历",
    "not a RINEX file: no 'END OF HEADER' line": "不是 RINEX 文件：没有“END OF HEADER”行",
    "not a RINEX file: expected 'RINEX VERSION / TYPE' on the first line": "不是 RINEX 文件：首行应为“RINEX VERSION / TYPE”",
    "unreadable RINEX version {version!r}": "无法识别的 RINEX 版本 {version!r}",
    "expected a RINEX observation file (type O), found type {file_type!r}": "应为 RINEX 观测文件（类型 O），实为类型 {file_type!r}",
    "unreadable {label}: expected three F14.4 numbers": "无法读取 {label}：应为三个 F14.4 格式的数",
    "{label}: non-finite value {text!r}: expected three F14.4 numbers in metres": "{label}：非有限值 {text!r}：应为三个以米为单位的 F14.4 格式的数",
    "cannot read the file: {strerror}": "无法读取文件：{strerror}",
    "damaged gzip file: {err}": "gzip 文件已损坏：{err}",
    "a zip archive: unpack it and give the RINEX files it holds": "这是 zip 压缩包：请解压并给出其中的 RINEX 文件",
    "Unix-compressed (.Z) file and the ncompress package is not installed: decompress it first (uncompress / gzip -d)":
        "Unix 压缩（.Z）文件，且未安装 ncompress 包：请先解压（uncompress / gzip -d）",
    "damaged .Z (compress) file: {err}": ".Z（compress）文件已损坏：{err}",
    "Compact RINEX (Hatanaka) and the hatanaka package is not installed: pip install hatanaka, or restore it with CRX2RNX first":
        "Compact RINEX（Hatanaka）格式，且未安装 hatanaka 包：请 pip install hatanaka，或先用 CRX2RNX 还原",
    "Compact RINEX of more than {limit_gib} GiB: restore it with CRX2RNX first": "Compact RINEX 超过 {limit_gib} GiB：请先用 CRX2RNX 还原",
    "damaged Compact RINEX (Hatanaka) file: {err}": "Compact RINEX（Hatanaka）文件已损坏：{err}",
    "inflates to more than {limit_mib:,.0f} MiB ({st_size:,} bytes compressed; the limit is {max_decompression_ratio} times the compressed size, at least {min_mib} MiB, at most {max_gib} GiB): not a plausible RINEX file (a damaged or hostile archive?)":
        "解压后超过 {limit_mib:,.0f} MiB（压缩后 {st_size:,} 字节；上限为压缩大小的 {max_decompression_ratio} 倍，至少 {min_mib} MiB，至多 {max_gib} GiB）：不像是 RINEX 文件（压缩包损坏或恶意构造？）",
    "negative standard deviation {sigma}": "标准差为负：{sigma}",
    "{name} {value} deg out of range": "{name} {value}° 超出范围",
    "to ({end:g}) is before from ({start:g}): give the smaller value first": "to（{end:g}）在 from（{start:g}）之前：请先给较小的值",
    "profile: only a turnout is assessed with a profile of its own, not a {kind}": "profile：只有道岔按其自身的标准评定，{kind} 不行",
    "{column}: expected a number, found {quoted}": "{column}：应为数值，实为 {quoted}",
    "{column}: expected a finite number, found {quoted}": "{column}：应为有限数值，实为 {quoted}",
    "is a folder, expected a file": "这是文件夹，应为文件",
    "not UTF-8 text ({reason} at byte {start})": "不是 UTF-8 文本（第 {start} 字节处 {reason}）",
    "expected at least 4 fields ({header}), found {count}": "应至少有 4 个字段（{header}），实有 {count} 个",
    "kind: expected one of {event_kinds}, found {quoted}": "kind：应为 {event_kinds} 之一，实为 {quoted}",
    "unit: expected one of {units}, found {quoted}": "unit：应为 {units} 之一，实为 {quoted}",
    "format not recognised: name it explicitly (one of {formats})": "无法识别格式：请明确指定（{formats} 之一）",
    "unknown option {unknown!r} for format {name} (known: {known})": "格式 {name} 没有选项 {unknown!r}（可用：{known}）",
    "latitude {lat_deg} deg: expected -90 to 90 degrees": "纬度 {lat_deg}°：应在 -90° 至 90° 之间",
    "longitude {lon_deg} deg: expected -180 to 360 degrees": "经度 {lon_deg}°：应在 -180° 至 360° 之间",
    "negative {what} standard deviation {sigma}": "{what} 标准差为负：{sigma}",
    "word {position} ({text}): {what} in {get} is not read: expected unit digit (position 6) {known}{value}":
        "第 {position} 个字（{text}）：不读取以 {get} 表示的 {what}：单位位（第 6 位）应为 {known}{value}",
    "word {position} ({text}): expected digits after the sign, found {quoted}": "第 {position} 个字（{text}）：符号之后应为数字，实为 {quoted}",
    "word {position} ({text}): expected DDDMMSSs with minutes and seconds below 60": "第 {position} 个字（{text}）：应为 DDDMMSSs，分和秒小于 60",
    "word {position} ({text}): expected a number, found {quoted}": "第 {position} 个字（{text}）：应为数值，实为 {quoted}",
    "a station block (words {has}) needs the set-up's name in word {point_id}": "测站块（字 {has}）需要在字 {point_id} 中给出设站名",
    "a pointing needs words 11 (point id), 21 (Hz), 22 (V) and 31 (slope distance): word {missing} missing":
        "一次照准需要字 11（点号）、21（Hz）、22（V）和 31（斜距）：缺少字 {missing}",
    "a pointing before any station block: expected a block with the set-up's name (word 11) and its station words 84-86 or 88 first":
        "照准出现在任何测站块之前：应先有含设站名（字 11）及其测站字 84-86 或 88 的块",
    "word {position} ({text}): Hz outside the full circle": "第 {position} 个字（{text}）：Hz 超出整圆",
    "word {position} ({text}): V = {degrees:.5f} deg is not a zenith angle of face I or II": "第 {position} 个字（{text}）：V = {degrees:.5f}° 不是盘左或盘右的天顶角",
    "word {position} ({text}): expected a positive slope distance": "第 {position} 个字（{text}）：斜距应为正",
    "prism pointing {target}: expected its time [s of GPS week] in word {time} (remark 1)": "棱镜照准 {target}：字 {time}（备注 1）中应给出其时间 [GPS 周秒]",
    "no pointing: expected blocks with words 11, 21, 22 and 31": "没有照准：应有含字 11、21、22 和 31 的块",
    "word {time}: prism time {time_s} s is not after the previous prism pointing's: times must increase": "字 {time}：棱镜时间 {time_s} s 不晚于上一次棱镜照准的时间：时间必须递增",
    "a point needs words 11 (id), 81 (E), 82 (N) and 83 (H): word {missing} missing": "一个点需要字 11（点号）、81（E）、82（N）和 83（H）：缺少字 {missing}",
    "word {position}: point {point} is given twice (first on line {first_line})": "第 {position} 个字：点 {point} 出现两次（首次在第 {first_line} 行）",
    "no point: expected blocks with words 11, 81, 82 and 83": "没有点：应有含字 11、81、82 和 83 的块",
    "word {position} ({quoted}): expected a GSI word: a two-digit word index, four characters of information, a sign and the data":
        "第 {position} 个字（{quoted}）：应为 GSI 字：两位字号、四个信息字符、符号和数据",
    "word {position} ({text}): word index {index} appears twice in the block": "第 {position} 个字（{text}）：字号 {index} 在块中出现两次",
    "not a readable NumPy .npy file ({exc})": "不是可读取的 NumPy .npy 文件（{exc}）",
    "expected a 1-D structured array with fields {expected}, found dtype {dtype} with shape {shape}":
        "应为含字段 {expected} 的一维结构化数组，实为 dtype {dtype}，形状 {shape}",
    "field {name!r}: expected {base} with shape {shape}; the file's fields are {dtype}": "字段 {name!r}：应为形状 {shape} 的 {base}；文件的字段为 {dtype}",
    "empty file: no records": "空文件：没有记录",
    "the file ends after {read} of its {n} records": "文件在其 {n} 条记录中的第 {read} 条之后结束",
    "{name} is {value}: expected finite numbers": "{name} 为 {value}：应为有限数值",
    "cannot be read: {reason}": "无法读取：{reason}",
    "the time tag spans {span_s:.3f} s but the record {file} counts {counter_span_s:.3f} s (time column in ms): not this record's tag, or the time column is not the logger's millisecond counter":
        "时间标签跨度为 {span_s:.3f} s，而记录 {file} 计得 {counter_span_s:.3f} s（时间列以 ms 计）：不是该记录的时间标签，或时间列不是记录器的毫秒计数",
    "option {option} = {value!r}: expected one of {allowed}": "选项 {option} = {value!r}：应为 {allowed} 之一",
    "option {option}: expected 3 column indices, found {count}": "选项 {option}：应为 3 个列序号，实有 {count} 个",
    "option sensor_rpy_deg: expected 3 angles (roll, pitch, yaw)": "选项 sensor_rpy_deg：应为 3 个角度（横滚、俯仰、航向）",
    "option {option}: column index {index} does not exist, the file has {width} columns (indices 0 to {last})":
        "选项 {option}：列序号 {index} 不存在，文件共 {width} 列（序号 0 至 {last}）",
    "need at least 2 samples to integrate rates into increments": "至少需要 2 个采样才能将速率积分为增量",
    "velocity increments imply a median specific force of {specific_force:.0f} m/s^2 at {rate_hz:.0f} Hz: the file seems to hold accelerations (m/s^2), expected velocity increments (m/s)":
        "按 {rate_hz:.0f} Hz 计，速度增量对应的比力中位数为 {specific_force:.0f} m/s^2：文件中似乎是加速度（m/s^2），应为速度增量（m/s）",
    "angle increments imply a median turn rate of {turn_rate:.0f} rad/s at {rate_hz:.0f} Hz: the file seems to hold angular rates, expected angle increments (rad)":
        "按 {rate_hz:.0f} Hz 计，角度增量对应的角速率中位数为 {turn_rate:.0f} rad/s：文件中似乎是角速率，应为角度增量（rad）",
    "pulse length unknown: give pulse_length_m (reader option or survey.toml) or a '# pulse_length_m = 0.001' header line":
        "脉冲长度未知：请给出 pulse_length_m（读取选项或 survey.toml），或文件头行“# pulse_length_m = 0.001”",
    "header pulse_length_m = {from_header!r}: expected a number": "文件头 pulse_length_m = {from_header!r}：应为数值",
    "pulse_length_m = {pulse_length_m}: expected a positive length": "pulse_length_m = {pulse_length_m}：应为正的长度",
    "pulse count {counts}: expected an integer": "脉冲计数 {counts}：应为整数",
    "incomplete ephemeris record: expected 8 lines": "星历记录不完整：应有 8 行",
    "expected an ephemeris record: PRN and clock epoch (year month day hour minute second)": "应为星历记录：PRN 及钟差历元（年 月 日 时 分 秒）",
    "no GPS ephemerides after the header": "文件头之后没有 GPS 星历",
    "expected a number in columns {first}-{last}, found {field!r}": "第 {first}-{last} 列应为数值，实为 {field!r}",
    "expected a RINEX navigation file with GPS ephemerides (type N, system G or M)": "应为含 GPS 星历的 RINEX 导航文件（类型 N，系统 G 或 M）",
    "invalid calendar date or time: expected yyyy/mm/dd hh:mm:ss.sss": "日期或时间无效：应为 yyyy/mm/dd hh:mm:ss.sss",
    "invalid GPS week or time of week: expected 'week tow'": "GPS 周或周内秒无效：应为“week tow”",
    "Q = {quality}: expected an integer 0 to {max_quality}": "Q = {quality}：应为 0 至 {max_quality} 的整数",
    "solution form {form!r} is not supported: expected latitude/longitude/height (RTKLIB out-solformat=llh)":
        "不支持解的形式 {form!r}：应为纬度/经度/高度（RTKLIB out-solformat=llh）",
    "empty file: no data lines": "空文件：没有数据行",
    "empty file: no solution epochs (a survey without any GNSS, in a tunnel, leaves [files.gnss] out of its survey.toml)":
        "空文件：没有解算历元（完全没有 GNSS 的测量，如隧道内，请从 survey.toml 中删去 [files.gnss]）",
    "{what}.{alias}: the same as {what}.{key}; give one of them": "{what}.{alias}：与 {what}.{key} 相同；只给其中之一",
    "files: missing table [files.<role>] (the imu role is required)": "files：缺少表 [files.<role>]（必须有 imu 角色）",
    "files.odometer_right: a second odometer needs the first, [files.odometer] (or [files.odometer_left]); a survey with one odometer gives it as [files.odometer], on whichever rail, with its lever arm trolley.imu_to_odometer_m":
        "files.odometer_right：第二个里程计需要第一个 [files.odometer]（或 [files.odometer_left]）；只有一个里程计的测量把它写作 [files.odometer]（不论在哪根钢轨上），其杠杆臂为 trolley.imu_to_odometer_m",
    "files.{role}: missing (required role)": "files.{role}：缺失（必需的角色）",
    "files.gnss: give either a GNSS solution [files.gnss] or raw observations [gnss_raw], not both":
        "files.gnss：给出 GNSS 解 [files.gnss] 或原始观测值 [gnss_raw] 之一，不能两者都给",
    "files: no position source: give a GNSS solution [files.gnss], raw GNSS observations [gnss_raw], total-station prism fixes [files.prism] or raw total-station observations [files.total_station]; or, for a relative survey (gauge, cant, twist and chord checks, no coordinates), the odometer [files.odometer] with stops about every 60 m":
        "files：没有位置来源：请给出 GNSS 解 [files.gnss]、GNSS 原始观测值 [gnss_raw]、全站仪棱镜定位 [files.prism] 或全站仪原始观测值 [files.total_station]；或者，对于相对测量（轨距、超高、扭曲及弦测检测，无坐标），给出里程计 [files.odometer] 并约每 60 m 停车一次",
    "{key}: unknown role (expected one of {roles})": "{key}：未知角色（应为 {roles} 之一）",
    "{key}: expected a table with path and format": "{key}：应为含 path 和 format 的表",
    "{key}.time_offset_s: only the files of {timed_roles} take one (the IMU's clock is the survey's time reference)":
        "{key}.time_offset_s：只有 {timed_roles} 的文件可以设置（IMU 的时钟是测量的时间基准）",
    "{key}.time_offset_s: expected the seconds the file's time stamps run late against the IMU's clock (a number within ±{max_given_time_offset_s:g} s), found {time_offset_s!r}":
        "{key}.time_offset_s：应为文件时间戳相对 IMU 时钟滞后的秒数（±{max_given_time_offset_s:g} s 以内的数），实为 {time_offset_s!r}",
    "{key}.path: expected a file name relative to the survey folder": "{key}.path：应为相对于测量文件夹的文件名",
    "{key}.path: file not found: {path}": "{key}.path：找不到文件：{path}",
    "{key}.format: expected a format name ({formats})": "{key}.format：应为格式名（{formats}）",
    "{key}.format: unknown format {name!r} (expected one of {formats})": "{key}.format：未知格式 {name!r}（应为 {formats} 之一）",
    "{key}.format: {name} does not hold {role} data (use one of {fitting})": "{key}.format：{name} 不含 {role} 数据（请使用 {fitting} 之一）",
    "{key}.{option}: unknown option for format {name} (known: {known})": "{key}.{option}：格式 {name} 没有此选项（可用：{known}）",
    "{key}.{option}: {why}": "{key}.{option}：{why}",
    "trolley: missing table [trolley] (lever arms and reference rail)": "trolley：缺少表 [trolley]（杠杆臂及基准轨）",
    "trolley.{key}: unknown key (expected {keys})": "trolley.{key}：未知的键（应为 {keys}）",
    "trolley.{key}: missing (required with files.{users}; 3 numbers [m], IMU body frame FRD)": "trolley.{key}：缺失（有 files.{users} 时必需；3 个数 [m]，IMU 载体坐标系 FRD）",
    "trolley.{key}: expected 3 numbers [m], found {table!r}": "trolley.{key}：应为 3 个数 [m]，实为 {table!r}",
    "trolley.reference_rail: expected \"left\" or \"right\", found {reference_rail!r}": "trolley.reference_rail：应为 \"left\" 或 \"right\"，实为 {reference_rail!r}",
    "trolley.mounting_rpy_deg: expected 3 numbers [deg], found {table!r}": "trolley.mounting_rpy_deg：应为 3 个数 [°]，实为 {table!r}",
    "trolley.rail_centre_spacing_m: expected a positive number [m], found {spacing!r}": "trolley.rail_centre_spacing_m：应为正数 [m]，实为 {spacing!r}",
    "trolley.beam_wheel_spacing_m: expected the spacing of the twin-wheel beam's side wheels, 0 .. {max_beam_wheel_spacing_m:g} m (0: no curve correction), found {beam!r}":
        "trolley.beam_wheel_spacing_m：应为双轮横梁侧轮的间距，0 .. {max_beam_wheel_spacing_m:g} m（0：不作曲线修正），实为 {beam!r}",
    "file not found: the survey folder needs a survey.toml": "找不到文件：测量文件夹中需要 survey.toml",
    "{key}: unknown table (expected [survey], [files.<role>], [trolley], [gnss_raw], [start])": "{key}：未知的表（应为 [survey]、[files.<role>]、[trolley]、[gnss_raw]、[start]）",
    "survey: missing table [survey] (name, gps_week, imu_profile, description)": "survey：缺少表 [survey]（name、gps_week、imu_profile、description）",
    "survey.{key}: unknown key (expected {keys})": "survey.{key}：未知的键（应为 {keys}）",
    "survey.name: expected a non-empty text": "survey.name：应为非空文本",
    "survey.gps_week: expected a whole GPS week number, found {gps_week!r}": "survey.gps_week：应为整数 GPS 周，实为 {gps_week!r}",
    "survey.{key}: expected text, found {survey!r}": "survey.{key}：应为文本，实为 {survey!r}",
    "survey.imu_profile: file not found: {imu_profile} (a .toml path is relative to the survey folder; or name a shipped profile)":
        "survey.imu_profile：找不到文件：{imu_profile}（.toml 路径相对于测量文件夹；或给出随附的配置名）",
    "start: expected a table [start] with station_m": "start：应为含 station_m 的表 [start]",
    "start.{key}: unknown key (expected {keys})": "start.{key}：未知的键（应为 {keys}）",
    "start.station_m: expected the design station [m] the trolley starts on, found {value!r}": "start.station_m：应为小车起点的设计里程 [m]，实为 {value!r}",
    "start.{key}: expected metres from the design (within 10 m), found {table!r}": "start.{key}：应为相对设计的米数（10 m 以内），实为 {table!r}",
    "start.sigma_m: expected the 1-sigma [m] of the start point, 0.001 .. 10, found {sigma!r}": "start.sigma_m：应为起点的 1σ [m]，0.001 .. 10，实为 {sigma!r}",
    "start.facing: expected \"increasing\" or \"decreasing\" (the stations the trolley's x axis points to), found {facing!r}":
        "start.facing：应为 \"increasing\" 或 \"decreasing\"（小车 x 轴所指方向的里程），实为 {facing!r}",
    "files.{role}{name}: time span {time_s:.3f}..{time_s2:.3f} s does not overlap the IMU's {time_s3:.3f}..{time_s4:.3f} s (different time scales, or a file of another day or run?)":
        "files.{role}{name}：时间段 {time_s:.3f}..{time_s2:.3f} s 与 IMU 的 {time_s3:.3f}..{time_s4:.3f} s 不重叠（时间尺度不同，或是另一天或另一趟的文件？）",
    "files.{role}: data is from GPS week {gps_week}, survey.gps_week says {gps_week2}": "files.{role}：数据属于 GPS 周 {gps_week}，而 survey.gps_week 为 {gps_week2}",
    "gnss_raw: the survey holds raw GNSS observations; process it in a project (PPK) first": "gnss_raw：该测量含 GNSS 原始观测值；请先在项目中处理（PPK）",
    "files.gnss: the survey has its own GNSS solution; a computed one is not used": "files.gnss：该测量有自己的 GNSS 解；不使用计算出的解",
    "gnss_raw.{key}[{i}]: expected a file name, found {name!r}": "gnss_raw.{key}[{i}]：应为文件名，实为 {name!r}",
    "gnss_raw.{key}[{i}]: file not found: {name}": "gnss_raw.{key}[{i}]：找不到文件：{name}",
    "gnss_raw.rover: give either rover (RINEX observations) or rover_log (a receiver log)": "gnss_raw.rover：给出 rover（RINEX 观测值）或 rover_log（接收机记录）之一",
    "gnss_raw.rover_log_format: expected a receiver format name with rover_log, found {log_format!r}": "gnss_raw.rover_log_format：有 rover_log 时应为接收机格式名，实为 {log_format!r}",
    "gnss_raw.base_point: expected a control point name of the project or \"{base_from_rinex_header}\", found {base_point!r}":
        "gnss_raw.base_point：应为项目的控制点名或 \"{base_from_rinex_header}\"，实为 {base_point!r}",
    "gnss_raw.base_antenna_height_m: expected a height above the mark in metres, found {height!r}": "gnss_raw.base_antenna_height_m：应为标志之上的高度（米），实为 {height!r}",
    "gnss_raw.base_antenna_height_m: not used with base_point = \"rinex-header\" (the header's ANTENNA: DELTA H applies); remove it or name a control point":
        "gnss_raw.base_antenna_height_m：base_point = \"rinex-header\" 时不使用（采用文件头的 ANTENNA: DELTA H）；请删除它或给出控制点",
    "gnss_raw.base_antenna_height_m: missing (the base antenna's reference point above control point {base_point}, metres)":
        "gnss_raw.base_antenna_height_m：缺失（基准站天线参考点在控制点 {base_point} 之上的高度，米）",
    "gnss_raw.base_antenna_type: expected an ANTEX antenna name (up to 20 characters), found {antenna_type!r}": "gnss_raw.base_antenna_type：应为 ANTEX 天线名（最多 20 个字符），实为 {antenna_type!r}",
    "gnss_raw: expected a table (rover, base, navigation, base_point, ...)": "gnss_raw：应为表（rover、base、navigation、base_point 等）",
    "gnss_raw.{key}: unknown key (expected {keys})": "gnss_raw.{key}：未知的键（应为 {keys}）",
    "gnss_raw.{key}: missing (a file name relative to the survey folder)": "gnss_raw.{key}：缺失（相对于测量文件夹的文件名）",
    "gnss_raw.{key}: expected a file name relative to the survey folder, found {value!r}": "gnss_raw.{key}：应为相对于测量文件夹的文件名，实为 {value!r}",
    "gnss_raw.{key}: file not found: {value}": "gnss_raw.{key}：找不到文件：{value}",
    "header gps_week = {value!r}: expected an integer": "文件头 gps_week = {value!r}：应为整数",
    "line longer than the limit of {max_line_chars:,} characters: not a text table of this kind": "行长超过 {max_line_chars:,} 个字符的上限：不是此类文本表",
    "more than the limit of {max_lines:,} lines: not a plausible survey file (a 200 Hz IMU records 17 million lines a day)":
        "超过 {max_lines:,} 行的上限：不像是测量文件（200 Hz 的 IMU 一天记录 1700 万行）",
    "expected {wanted} columns, found {count}": "应有 {wanted} 列，实有 {count} 列",
    "column {number} ({name})": "第 {number} 列（{name}）",
    "column {number}": "第 {number} 列",
    "{column} is empty": "{column} 为空",
    "could not be parsed as numbers ({parser_message})": "无法解析为数值（{parser_message}）",
    "expected {wanted} columns, found {shape}": "应有 {wanted} 列，实有 {shape} 列",
    "{column} is {value}: expected a finite number": "{column} 为 {value}：应为有限数值",
    "duplicate time stamp {time_s:.6f} (same as {previous})": "时间戳 {time_s:.6f} 重复（与 {previous} 相同）",
    "time stamp {time_s:.6f} is earlier than {time_s2:.6f} on {previous}: time stamps must increase": "时间戳 {time_s:.6f} 早于 {previous} 的 {time_s2:.6f}：时间戳必须递增",
    "{label}: expected a number, found {quoted}": "{label}：应为数值，实为 {quoted}",
    "{label} is {value}: expected a finite number": "{label} 为 {value}：应为有限数值",
    "{what} {point!r} appears twice (also on line {line_of_row})": "{what} {point!r} 出现两次（另见第 {line_of_row} 行）",
    "binary data (a NUL byte), not a text file: a disk image, an archive or a file in UTF-16? Save text as UTF-8 or ASCII":
        "二进制数据（含 NUL 字节），不是文本文件：是磁盘映像、压缩包或 UTF-16 文件？请将文本存为 UTF-8 或 ASCII",
    "file not found: the record's RTKLIB time tag (<file>.tag) is needed to put its logger clock on GPST":
        "找不到文件：需要该记录的 RTKLIB 时间标签（<file>.tag）才能把记录器时钟归算到 GPST",
    "not an RTKLIB time tag: expected a {header_bytes}-byte header starting {magic!r} and the start time":
        "不是 RTKLIB 时间标签：应为以 {magic!r} 开头、含起始时间的 {header_bytes} 字节文件头",
    "{count} bytes of ticks and file positions after the header: expected pairs of uint32 tick and uint32 (or uint64) file position, both never decreasing":
        "文件头之后的计时与文件位置共 {count} 字节：应为成对的 uint32 计时与 uint32（或 uint64）文件位置，二者均不递减",
    "start time fraction {fraction!r}: expected 0 <= fraction < 1": "起始时间小数部分 {fraction!r}：应满足 0 <= fraction < 1",
    "larger than the limit of {limit_mib} MiB for a settings file": "超过设置文件 {limit_mib} MiB 的上限",
    "not valid TOML: {exc}": "不是有效的 TOML：{exc}",
    "not UTF-8 text: {exc}": "不是 UTF-8 文本：{exc}",
    "{name} = {value} {angle_unit} is outside {low:g}..{high:g} {angle_unit}": "{name} = {value} {angle_unit} 超出 {low:g}..{high:g} {angle_unit}",
    "slope distance D = {slope} m: expected a positive distance": "斜距 D = {slope} m：应为正的距离",
    "prism time {time_s} s is not after the previous prism pointing's: times must increase": "棱镜时间 {time_s} s 不晚于上一次棱镜照准的时间：时间必须递增",
    "point {point} is given twice (first on line {line_of_row})": "点 {point} 出现两次（首次在第 {line_of_row} 行）",
    "median gauge {median:g} mm is implausible: expected millimetres (is the file in metres?)": "轨距中位数 {median:g} mm 不合理：应以毫米计（文件是否以米为单位？）",
    "expected 3 columns (t, volts, temperature [°C]) because the calibration gives a temperature coefficient (temperature_coefficient_mm_per_c), found 2":
        "标定给出了温度系数（temperature_coefficient_mm_per_c），因此应有 3 列（t、电压、温度 [°C]），实有 2 列",
    "a third column (temperature) but the calibration gives no temperature coefficient: give temperature_coefficient_mm_per_c and calibration_temperature_c (K_T = 0 for a sensor that needs none)":
        "有第三列（温度），但标定未给出温度系数：请给出 temperature_coefficient_mm_per_c 和 calibration_temperature_c（无需温度补偿的传感器 K_T = 0）",
    "temperature {temperature_c:g}: expected degrees Celsius, {low:g} .. {high:g}": "温度 {temperature_c:g}：应为摄氏度，{low:g} .. {high:g}",
    "the calibration gives a median gauge of {median:g} mm: expected millimetres (k_mm_per_v in mm/V and b_mm in mm)":
        "按标定得到的轨距中位数为 {median:g} mm：应以毫米计（k_mm_per_v 单位 mm/V，b_mm 单位 mm）",
    "cannot read the Dask security settings: {strerror}": "无法读取 Dask 安全设置：{strerror}",
    "not a Dask YAML configuration file: {err}": "不是 Dask YAML 配置文件：{err}",
    "expected Dask settings under distributed.comm (tls: ca-file, client: cert, key; require-encryption)":
        "distributed.comm 下应为 Dask 设置（tls：ca-file、client：cert、key；require-encryption）",
    "distributed.comm.tls.{key}: file not found: {file}": "distributed.comm.tls.{key}：找不到文件：{file}",
    "{read_as}only {match_pct:.0f} % of consecutive sleeper pulses lie one sleeper spacing ({spacing:.3f} m, the median) apart along the odometer distance ({odometer_label}); expected at least {min_match_pct:.0f} % and no better match at another time{hint}":
        "{read_as}按里程计距离（{odometer_label}），相邻轨枕脉冲相隔一个轨枕间距（{spacing:.3f} m，中位数）的只占 {match_pct:.0f} %；应至少为 {min_match_pct:.0f} %，且在其他时刻没有更好的匹配{hint}",
    "{read_as}{text}; an offset of {max_offset_s:g} s or more is refused: likely {cause}; {remedy}": "{read_as}{text}；{max_offset_s:g} s 及以上的偏移不予接受：可能是{cause}；{remedy}",
    "read as {format}: ": "按 {format} 读取：",
    "h and H are swapped (the file's columns are id lat lon h H)": "h 与 H 颠倒（文件各列应为 id lat lon h H）",
    "heights in another datum or unit, or H is not a normal height": "高程属于其他基准或单位，或 H 不是正常高",
    " (x{ratio:.3g} the nominal: another unit?)": "（为名义值的 {ratio:.3g} 倍：单位不同？）",
    "a distance in millimetres": "距离以毫米计",
    "a wrong pulse length (pulse_length_m = {pulse_length_m:g} m)": "脉冲长度有误（pulse_length_m = {pulse_length_m:g} m）",
    "a distance in another unit, or a wrong calibration": "距离单位不同，或标定有误",
    "; shifted by {shift_s:+.1f} s they would match ({score_pct:.0f} %): a file on another time scale":
        "；平移 {shift_s:+.1f} s 后即可匹配（{score_pct:.0f} %）：文件使用了另一时间尺度",
    ": a file of another survey or run, or a detector that misses or doubles pulses": "：是另一次测量或另一趟的文件，或检测器漏计、重计脉冲",
    "{leap_s} s is GPS - UTC (leap seconds): GNSS times in UTC read as GPST (an RTKLIB .pos written in UTC, or without its header)":
        "{leap_s} s 即 GPS - UTC（闰秒）：UTC 的 GNSS 时间被当作 GPST 读取（RTKLIB .pos 以 UTC 写出，或缺少文件头）",
    "the loggers' clocks are not synchronised, or a file of another survey": "各记录器时钟未同步，或是另一次测量的文件",
    "if it is the sensor's known latency, give time_offset_s = {offset_s:.2f} in [files.{role}] of survey.toml":
        "若这是传感器已知的延迟，请在 survey.toml 的 [files.{role}] 中给出 time_offset_s = {offset_s:.2f}",
    "the IMU's clock is the reference the others are put on": "IMU 的时钟是其他文件归算到的基准",
    "not a repeatability summary written by insrail compare ({error})": "不是 insrail compare 写出的重复性汇总（{error}）",
    "missing: run insrail compare again": "缺失：请重新运行 insrail compare",
    "expected numbers after the label column ({error})": "标签列之后应为数值（{error}）",
    "no column {missing!r} although repeatability.toml lists {parameter!r}": "repeatability.toml 列有 {parameter!r}，但没有列 {missing!r}",
    "{key}: latitude {lat} / longitude {lon} out of range (degrees)": "{key}：纬度 {lat} / 经度 {lon} 超出范围（度）",
    "{key_path}: expected tables [{key_path}.<name>]": "{key_path}：应为表 [{key_path}.<name>]",
    "{key}: expected a table with {geodetic_keys} or {engineering_keys}": "{key}：应为含 {geodetic_keys} 或 {engineering_keys} 的表",
    "{key}.{k}: unknown key (expected {geodetic_keys} or {engineering_keys})": "{key}.{k}：未知的键（应为 {geodetic_keys} 或 {engineering_keys}）",
    "{key}: give either {geodetic_keys} (geodetic) or {engineering_keys} (engineering system)": "{key}：给出 {geodetic_keys}（大地坐标）或 {engineering_keys}（工程坐标系）之一",
    "{key}.{k}: missing": "{key}.{k}：缺失",
    "{key}.{k}: expected a number, found {value!r}": "{key}.{k}：应为数值，实为 {value!r}",
    "no quality.csv (the survey's predicted 1-sigma): process it again": "没有 quality.csv（测量的预测 1σ）：请重新处理",
    "fewer than two valid sleepers with the {rail} rail: nothing to compare": "{rail} 轨的有效轨枕少于两根：无可比较",
    "gnss_raw.base_point: unknown control point {base_point!r}: not in the project's [geodesy.control_points] (known: {known}); or write base_point = \"rinex-header\" for the approximate header position":
        "gnss_raw.base_point：未知控制点 {base_point!r}：不在项目的 [geodesy.control_points] 中（已有：{known}）；或写 base_point = \"rinex-header\" 以采用文件头的近似位置",
    "gnss_raw.{key}: expected a list of file names relative to the survey folder{least}": "gnss_raw.{key}：应为相对于测量文件夹的文件名列表{least}",
    " (at least one)": "（至少一个）",
    "{key_path}.{key}: unknown key (expected model, points)": "{key_path}.{key}：未知的键（应为 model、points）",
    "{where}.{key}: unknown key (expected {keys})": "{where}.{key}：未知的键（应为 {keys}）",
    "{key_path}: expected a table with model and points": "{key_path}：应为含 model 和 points 的表",
    "{key_path}.model: expected one of {models}, found {model!r}": "{key_path}.model：应为 {models} 之一，实为 {model!r}",
    "{key_path}.points: expected [{key_path}.points.<name>] tables, one per common point": "{key_path}.points：应为 [{key_path}.points.<name>] 表，每个公共点一个",
    "{where}: expected a table of {keys}": "{where}：应为含 {keys} 的表",
    "{where}: missing {missing}": "{where}：缺少 {missing}",
    "{where}.{key}: expected a number of metres, found {value!r}": "{where}.{key}：应为米数，实为 {value!r}",
    "{key_path}.points: local_height_m is given for some points only (all or none)": "{key_path}.points：只有部分点给出了 local_height_m（应全部给出或全不给）",
    "{key_path}: {error}": "{key_path}：{error}",
    "project file not found": "找不到项目文件",
    "unknown table (expected {tables})": "未知的表（应为 {tables}）",
    "missing table (the engineering coordinate system)": "缺少表（工程坐标系）",
    "expected true or false, found {processing!r}": "应为 true 或 false，实为 {processing!r}",
    "missing: without a design alignment the start station is needed": "缺失：没有设计线形时需要起点里程",
    "{problem} or \"{with_travel}\"": "{problem}或 \"{with_travel}\"",
    "expected a whole number, found {first_number!r}": "应为整数，实为 {first_number!r}",
    "expected [[sections]] entries with name and surveys": "应为含 name 和 surveys 的 [[sections]] 条目",
    "expected a table with name and surveys": "应为含 name 和 surveys 的表",
    "expected a name of letters, digits, '.', '_' or '-', found {name!r}": "应为由字母、数字、“.”、“_”或“-”组成的名称，实为 {name!r}",
    "{name!r} is already the name of a {kind} (both name a results folder)": "{name!r} 已是某个 {kind} 的名称（二者都用作结果文件夹名）",
    "expected a list of the project's survey names": "应为项目中测量名称的列表",
    "no survey named {run!r} (surveys: {known})": "没有名为 {run!r} 的测量（现有测量：{known}）",
    "a survey is named twice": "有测量名称重复",
    "from_m ({bounds}) must be below to_m ({bounds2})": "from_m（{bounds}）必须小于 to_m（{bounds2}）",
    "expected one of {overlap_rules}, found {overlap!r}": "应为 {overlap_rules} 之一，实为 {overlap!r}",
    "expected {strategies}, found {strategy!r}": "应为 {strategies}，实为 {strategy!r}",
    "expected at most {max_threshold_mm:g} mm, found {threshold:g}": "应不超过 {max_threshold_mm:g} mm，实为 {threshold:g}",
    "expected true or false, found {table!r}": "应为 true 或 false，实为 {table!r}",
    "expected a distance of 0 mm or more, found {value:g}": "应为 0 mm 及以上的距离，实为 {value:g}",
    "{min_lift_mm:g} mm is more than max_lift_mm ({max_lift_mm:g} mm)": "{min_lift_mm:g} mm 大于 max_lift_mm（{max_lift_mm:g} mm）",
    "expected [[redesign.fixed]] entries with from_m and to_m": "应为含 from_m 和 to_m 的 [[redesign.fixed]] 条目",
    "expected a table with from_m, to_m and optionally tolerance_mm": "应为含 from_m、to_m（可选 tolerance_mm）的表",
    "missing {keys}": "缺少 {keys}",
    "from_m ({start:g}) must be below to_m ({end:g})": "from_m（{start:g}）必须小于 to_m（{end:g}）",
    "expected 0 mm or more, found {tolerance:g}": "应为 0 mm 及以上，实为 {tolerance:g}",
    "expected a date like 2026-03-14, found {value!r}": "应为形如 2026-03-14 的日期，实为 {value!r}",
    "expected one of {paper_sizes}, found {paper!r}": "应为 {paper_sizes} 之一，实为 {paper!r}",
    "expected one of {languages}, found {language!r}": "应为 {languages} 之一，实为 {language!r}",
    "expected a table {{from_m = ..., to_m = ..., kmh = ...}}, found {entry!r}": "应为表 {{from_m = ..., to_m = ..., kmh = ...}}，实为 {entry!r}",
    "from_m ({start}) must be below to_m ({end})": "from_m（{start}）必须小于 to_m（{end}）",
    "expected one of {height_models}, found {model!r}": "应为 {height_models} 之一，实为 {model!r}",
    "expected a table {{number = ..., station_m = ...}} or {{number = ..., time_s = ...}}, found {table!r}":
        "应为表 {{number = ..., station_m = ...}} 或 {{number = ..., time_s = ...}}，实为 {table!r}",
    "expected a whole number, found {number!r}": "应为整数，实为 {number!r}",
    "give exactly one of station_m (chainage) or time_s (GPS seconds of week)": "station_m（里程）与 time_s（GPS 周秒）只给其一",
    "{events}, line {line}: a project's events are in chainage (station_m); an event in {unit} belongs in its survey's event file":
        "{events}，第 {line} 行：项目的事件以里程（station_m）表示；以 {unit} 表示的事件应写入其测量的事件文件",
    "expected at least one [[surveys]] entry with name and folder": "应至少有一个含 name 和 folder 的 [[surveys]] 条目",
    "expected a table with name and folder": "应为含 name 和 folder 的表",
    "duplicate survey name {name!r}": "测量名称 {name!r} 重复",
    "expected a folder path relative to the project": "应为相对于项目的文件夹路径",
    "not found: {folder}": "不存在：{folder}",
    "no {manifest_name} in {folder}": "{folder} 中没有 {manifest_name}",
    "trolley.imu_to_odometer_right_m: missing, and files.odometer_right is given (the second wheel's contact point: 3 numbers [m], IMU body frame FRD; in project.toml's [trolley] when the project gives one)":
        "trolley.imu_to_odometer_right_m：缺失，但给出了 files.odometer_right（第二个轮的接触点：3 个数 [m]，IMU 载体坐标系 FRD；项目有 [trolley] 时写在 project.toml 的 [trolley] 中）",
    "trolley.imu_to_odometer_right_m: the two odometer wheels lie {spacing:.3f} m apart across the track (the lever arms' y, in the trolley frame); on the two rails they run about trolley.rail_centre_spacing_m = {rail_centre_spacing_m:g} m apart (within {max_spacing_offset_m:g} m)":
        "trolley.imu_to_odometer_right_m：两个里程计轮横向相距 {spacing:.3f} m（杠杆臂的 y，小车坐标系）；在两根钢轨上它们应相距约 trolley.rail_centre_spacing_m = {rail_centre_spacing_m:g} m（误差 {max_spacing_offset_m:g} m 以内）",
    "{read_as}{partition}; an offset of {max_offset_s:g} s or more is refused": "{read_as}{partition}；{max_offset_s:g} s 及以上的偏移不予接受",
    "{read_as}the right wheel counts {scale_pct:+.2f} % against the left one ({left_label}) where both roll; two wheels on the rails differ by far less: likely a wrong pulse length or another survey's file":
        "{read_as}两轮都在滚动时，右轮计数相对左轮（{left_label}）相差 {scale_pct:+.2f} %；钢轨上的两个轮相差远小于此：可能是脉冲长度有误或是另一次测量的文件",
    "track.sleeper_anchor: {error}": "track.sleeper_anchor：{error}",
    "files.gauge: missing; the track reconstruction needs the gauge record": "files.gauge：缺失；轨道重建需要轨距记录",
    "no epoch of the reconstructed track has a chainage": "重建轨道的任何历元都没有里程",
    "benchmark {point_id}: height anomaly h - H = {zeta:.3f} m, beyond the ±{max_height_anomaly_m:.0f} m of the geoid anywhere on Earth ({columns}): a height in another unit or datum?":
        "水准点 {point_id}：高程异常 h - H = {zeta:.3f} m，超出全球任何地方大地水准面的 ±{max_height_anomaly_m:.0f} m（{columns}）：高程单位或基准不同？",
    "benchmark {point_id}: height anomaly h - H = {zeta:.3f} m against {median:.3f} m at the others ({columns}): h and H swapped on its line, or a typo?":
        "水准点 {point_id}：高程异常 h - H = {zeta:.3f} m，其他点为 {median:.3f} m（{columns}）：该行 h 与 H 颠倒，或有笔误？",
    "height anomaly h - H = {median:.3f} m at the benchmarks, but the geoid (EGM96) lies at {median2:.3f} m there, {offset:+.1f} m apart (local height datums differ from EGM96 by a few metres at most): likely {cause}":
        "水准点处的高程异常 h - H = {median:.3f} m，而该处大地水准面（EGM96）为 {median2:.3f} m，相差 {offset:+.1f} m（地方高程基准与 EGM96 至多相差几米）：可能是{cause}",
    "trolley.{name} = {arm} m: a lever arm on a trolley is at most {max_lever_arm_m:g} m (b frame, metres): millimetres given as metres?":
        "trolley.{name} = {arm} m：小车上的杠杆臂至多 {max_lever_arm_m:g} m（b 坐标系，米）：把毫米当成了米？",
    "trolley.rail_centre_spacing_m = {spacing:g} m: the distance between the rail centres (the cant base) is the gauge plus one rail head, {low:.3f} .. {high:.3f} m for the {gauge_mm:.0f} mm gauge of the tolerance profile{hint}":
        "trolley.rail_centre_spacing_m = {spacing:g} m：两钢轨中心的距离（超高基长）等于轨距加一个轨头宽，对容许偏差标准的 {gauge_mm:.0f} mm 轨距为 {low:.3f} .. {high:.3f} m{hint}",
    ": millimetres given as metres?": "：把毫米当成了米？",
    "{key}: {err}": "{key}：{err}",
    "{read_as}median gauge {median_mm:.1f} mm against the nominal {nominal_mm:.0f} mm of the tolerance profile{hint}; the file must hold the gauge in mm":
        "{read_as}轨距中位数 {median_mm:.1f} mm，而容许偏差标准的名义轨距为 {nominal_mm:.0f} mm{hint}；文件中的轨距必须以 mm 计",
    "{read_as}{outliers} of {count} readings lie more than {max_offset_mm:.0f} mm from the median {median_mm:.1f} mm: a faulty gauge sensor; repair or remove the record":
        "{read_as}{count} 个读数中有 {outliers} 个偏离中位数 {median_mm:.1f} mm 超过 {max_offset_mm:.0f} mm：轨距传感器故障；请修复或删除该记录",
    "{read_as}the odometer travels {scale:.4g} m per metre of GNSS ({gnss_label}) over {windows} windows of {scale_window_s:g} s; expected 1 within {max_error_pct:.0f} %: likely {cause}":
        "{read_as}在 {windows} 个 {scale_window_s:g} s 的窗口内，GNSS（{gnss_label}）每走 1 米里程计走 {scale:.4g} m；应为 1，误差 {max_error_pct:.0f} % 以内：可能是{cause}",
    "{read_as}the odometer's speed disagrees with the GNSS speed ({gnss_label}) by more than 10 % in {disagree_pct:.0f} % of the moving windows: a slipping wheel, a wrong time scale or another survey's file":
        "{read_as}在 {disagree_pct:.0f} % 的运动窗口中，里程计速度与 GNSS 速度（{gnss_label}）相差超过 10 %：车轮打滑、时间尺度有误或是另一次测量的文件",
    "{read_as}the odometer counts backwards: at {count} start(s) from rest the IMU moved forwards along its x axis while the distance decreased (a reversed odometer, or the sign of its counts); the distance must grow as the trolley moves along the IMU's x axis":
        "{read_as}里程计反向计数：在 {count} 次由静止起步时，IMU 沿其 x 轴前进而距离减小（里程计装反，或其计数符号相反）；小车沿 IMU 的 x 轴移动时距离必须增大",
    "no results for survey {survey!r}: process it first": "测量 {survey!r} 没有结果：请先处理",
    "not a valid summary file ({error})": "不是有效的汇总文件（{error}）",
    "result file missing: process the survey again": "结果文件缺失：请重新处理该测量",
    "expected the header 'number,label,...' of an insrail sleeper table": "表头应为 insrail 轨枕表的“number,label,...”",
    "expected {width} fields, found {count}": "应有 {width} 个字段，实有 {count} 个",
    "expected numbers in every column but the label": "除标签外各列应为数值",
    "expected {count} fields: {header}": "应有 {count} 个字段：{header}",
    "expected {count} numbers (or empty cells): {header}": "应有 {count} 个数值（或空单元格）：{header}",
    "missing: the section's overlap rule 'best' needs the predicted accuracy; process the survey again": "缺失：区段的重叠规则“best”需要预测精度；请重新处理该测量",
    "damaged cache file ({error}): delete it to recompute": "缓存文件已损坏（{error}）：删除后将重新计算",
    "set-up {setup}: CPIII point {point} is not in the CPIII file {file}": "设站 {setup}：CPIII 点 {point} 不在 CPIII 文件 {file} 中",
    "set-up {setup}: {error}": "设站 {setup}：{error}",
    "set-up {setup}: the CPIII points fit the observations to {fit} RMS, more than the {max_setup_rms_mm:.0f} mm a total station gives: {hint}":
        "设站 {setup}：CPIII 点与观测值的拟合 RMS 为 {fit}，超过全站仪应达到的 {max_setup_rms_mm:.0f} mm：{hint}",
    "no prism pointing (target 'prism'): the observations fix no trolley position": "没有棱镜照准（目标“prism”）：观测值无法确定小车位置",
    "its zenith angles are about {level_gon:.0f} where points at the instrument's height read 100 gon: angles in degrees read as gon? (set the reader option angle_unit = \"deg\")":
        "其天顶角约为 {level_gon:.0f}，而与仪器等高的点应读 100 gon：把度当成了 gon？（请设置读取选项 angle_unit = \"deg\"）",
    "the CPIII points lie {ratio:.0f} times farther apart than measured: coordinates in millimetres? (the CPIII file holds metres)":
        "CPIII 点间距是实测的 {ratio:.0f} 倍：坐标以毫米计？（CPIII 文件应以米计）",
    "the CPIII points lie {ratio:.0f} times closer together than measured: distances in millimetres?": "CPIII 点间距只有实测的 1/{ratio:.0f}：距离以毫米计？",
    "check that the CPIII file and the observations belong together (point names, units)": "请检查 CPIII 文件与观测值是否对应（点名、单位）",
    "profile: {error}": "profile：{error}",
    "key {key!r} given twice": "键 {key!r} 出现两次",
    "unknown column {column!r} in [{section}]; expected {allowed}": "[{section}] 中有未知列 {column!r}；应为 {allowed}",
    "a column is named twice in the header of [{file}]": "[{file}] 的表头中有列名重复",
    "[{file}] header lacks column(s) {missing}": "[{file}] 的表头缺少列 {missing}",
    "expected at most {count} fields ({header}), found {found}": "应至多有 {count} 个字段（{header}），实有 {found} 个",
    "{column}: expected a number, found {text!r}": "{column}：应为数值，实为 {text!r}",
    "{column}: expected a finite number, found {text!r}": "{column}：应为有限数值，实为 {text!r}",
    "type: expected line, clothoid or arc, found {type!r}": "type：应为 line（直线）、clothoid（缓和曲线）或 arc（圆曲线），实为 {type!r}",
    "{column}: {err}": "{column}：{err}",
    "cannot read the element table: {err}": "无法读取线元表：{err}",
    "section [{required}] is missing": "缺少节 [{required}]",
    "[alignment] lacks {key}": "[alignment] 缺少 {key}",
    "[alignment] needs exactly one of start_azimuth_deg or start_azimuth_gon": "[alignment] 需要 start_azimuth_deg 或 start_azimuth_gon 二者之一",
    "unknown section [{name}]; expected [alignment], {sections}": "未知节 [{name}]；应为 [alignment]，{sections}",
    "section [{name}] appears twice (first on line {line})": "节 [{name}] 出现两次（首次在第 {line} 行）",
    "expected a section header such as [alignment] before any data": "数据之前应有 [alignment] 等节标题",
    "expected 'key, value' in [alignment], found {count} fields": "[alignment] 中应为“key, value”，实有 {count} 个字段",
    "unknown key {key!r}; expected one of {expected}": "未知的键 {key!r}；应为 {expected} 之一",
    "cannot read the LandXML file: {err}": "无法读取 LandXML 文件：{err}",
    "not well-formed XML: {reason}": "XML 格式不正确：{reason}",
    "missing attribute {name!r}": "缺少属性 {name!r}",
    "attribute {name!r} is not a number: {text!r}": "属性 {name!r} 不是数值：{text!r}",
    "attribute {name!r} must be finite, got {text!r}": "属性 {name!r} 必须为有限值，实为 {text!r}",
    "expected {meaning}, found {text!r}": "应为 {meaning}，实为 {text!r}",
    "expected {meaning} as numbers, found {text!r}": "{meaning} 应为数值，实为 {text!r}",
    "expected finite {meaning}, found {text!r}": "{meaning} 应为有限值，实为 {text!r}",
    "missing child element <{child}>": "缺少子元素 <{child}>",
    "attribute 'rot' must be 'cw' or 'ccw', got {rot!r}": "属性“rot”必须为“cw”或“ccw”，实为 {rot!r}",
    "length {given} does not match the distance Start-End {length:.4f} m": "长度 {given} 与 Start-End 距离 {length:.4f} m 不符",
    "only crvType='arc' is supported, got {crv_type!r}": "只支持 crvType='arc'，实为 {crv_type!r}",
    "radius {radius} does not match the distance Center-Start {distance:.4f} m": "半径 {radius} 与 Center-Start 距离 {distance:.4f} m 不符",
    "only spiType='clothoid' is supported, got {spi_type!r}": "只支持 spiType='clothoid'，实为 {spi_type!r}",
    "unsupported geometry element <{tag}>; expected Line, Spiral or Curve": "不支持的几何元素 <{tag}>；应为 Line、Spiral 或 Curve",
    "expected one <CoordGeom>, found {count}": "应有一个 <CoordGeom>，实有 {count} 个",
    "no Line, Spiral or Curve elements": "没有 Line、Spiral 或 Curve 元素",
    "the first element must give its start direction (a Spiral needs <PI>)": "第一个元素必须给出其起始方向（Spiral 需要 <PI>）",
    "Start is {gap:.4f} m away from the end of the previous element (gap)": "Start 与上一元素终点相距 {gap:.4f} m（间隙）",
    "start direction differs from the previous element's end direction by {kink:.3e} rad (kink)": "起始方向与上一元素终点方向相差 {kink:.3e} rad（折角）",
    "End is {miss:.4f} m away from the end computed from the element's length and radii": "End 与按元素长度和半径算得的终点相距 {miss:.4f} m",
    "length {declared} differs from the sum of the element lengths {length_m:.4f} m": "长度 {declared} 与各元素长度之和 {length_m:.4f} m 不符",
    "staInternal {given} does not match {internal:.4f} m implied by staStart {start_station} and the equations before it":
        "staInternal {given} 与由 staStart {start_station} 及其前的断链推算的 {internal:.4f} m 不符",
    "no <ProfAlign name={profile_name!r}>": "没有 <ProfAlign name={profile_name!r}>",
    "several <ProfAlign> ({names}); choose one by name": "有多个 <ProfAlign>（{names}）；请按名称选择一个",
    "unsupported profile element <{tag}>; expected PVI, ParaCurve or CircCurve": "不支持的纵断面元素 <{tag}>；应为 PVI、ParaCurve 或 CircCurve",
    "expected at most one <Cant>, found {count}": "应至多有一个 <Cant>，实有 {count} 个",
    "attribute 'curvature' must be 'cw' or 'ccw', got {curvature!r}": "属性“curvature”必须为“cw”或“ccw”，实为 {curvature!r}",
    "imperial units are not supported; export in metres": "不支持英制单位；请以米导出",
    "linearUnit must be 'meter', got {unit!r}": "linearUnit 必须为“meter”，实为 {unit!r}",
    "the root element is <{tag}>, expected <LandXML>": "根元素为 <{tag}>，应为 <LandXML>",
    "no Alignments/Alignment element": "没有 Alignments/Alignment 元素",
    "the file holds several alignments ({names}); choose one by name": "文件中有多条线形（{names}）；请按名称选择一条",
    "no alignment named {name!r} (found {names})": "没有名为 {name!r} 的线形（现有：{names}）",
    "elements nested more than {max_depth} deep: not a LandXML alignment file": "元素嵌套超过 {max_depth} 层：不是 LandXML 线形文件",
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
    "inside its limit by three of the survey's stated 1-sigma of it, at least {margin_mm:g} mm): {direction}, lift "
    "{min_lift_mm:g} to {max_lift_mm:g} mm, slew at most "
    "{max_slew_mm:g} mm; largest lift {lift_mm:.1f} mm at {lift_at_m:.1f} m, largest slew {slew_mm:.1f} mm at "
    "{slew_at_m:.1f} m, {sleepers} sleepers moved; exceedances {before} before, {after} after the job. Signs: "
    "{convention}.":
        "每根轨枕处使线路通过 {profile} 各弦测检测（各项在限值内留出测量所述该项 1σ 的三倍、至少 {margin_mm:g} mm 的余量）"
        "的最小起道量与拨道量：{direction}，"
        "起道 {min_lift_mm:g} 至 {max_lift_mm:g} mm，拨道不超过 {max_slew_mm:g} mm；最大起道 {lift_mm:.1f} mm，位于 "
        "{lift_at_m:.1f} m；最大拨道 {slew_mm:.1f} mm，位于 {slew_at_m:.1f} m；移动轨枕 {sleepers} 根；超限：作业前 "
        "{before} 处，作业后 {after} 处。符号：{convention}。",
    "lift only": "只起不落",
    "lift or lower": "可起可落",
    "Fixed stretches": "固定点区段",
    "tolerance (mm)": "允许偏差（mm）",
    "value (mm)": "数值（mm）",
    "none": "无",
    "Where a bound holds, and where the track is not said to pass": "受限区段及不能判定通过的区段",
    "cannot pass: {what}": "无法通过：{what}",
    "passes by less than its uncertainty ({count} stretches): {what}": "通过余量小于测量不确定度（{count} 段）：{what}",
    "passes by less than its uncertainty: {what}": "通过余量小于测量不确定度：{what}",
    "not assessed: {what} (stated 1-sigma {sigma_mm:.2f} mm against the limit {limit_mm:.1f} mm)":
        "不评定：{what}（所述 1σ {sigma_mm:.2f} mm，限值 {limit_mm:.1f} mm）",
    "Where a check's value after the job is within its limit by less than three of the survey's stated 1-sigma "
    "({uncertain} stretches), the true track may not pass it; where the stated 1-sigma is too large for the "
    "limit ({not_assessed} checks), the check is not assessed after the job, as the processing does not "
    "assess it: neither is said to pass; both are listed below.":
        "作业后检测值距限值不足测量所述 1σ 三倍之处（{uncertain} 段），实际线路可能不通过；所述 1σ 相对限值过大之处"
        "（{not_assessed} 项检测），作业后不评定该项检测，与数据处理一致：两者均不判为通过，列于下表。",
    "Where the track is not said to pass after the job": "作业后不能判定通过的区段",
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
    "profile's chord checks by at least the survey's uncertainty (docs/tamping.md), except in the stretches "
    "summary.toml lists (cannot pass, passes by less than its uncertainty, not assessed); cant_mm = the cant after "
    "the job":
        "左轨起道、右轨起道、拨道：钢轨（线路）按此量移动后即以不小于测量不确定度的余量通过容许偏差标准的各项弦测检测，"
        "summary.toml 所列区段除外（无法通过、通过余量小于测量不确定度、不评定）；作业后超高：作业完成后的超高",
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
    "{consistent} of {sections} sections of {section_m:.0f} m consistent with their 1-sigma{bad}{resets}{detours}"
    "{steps}{missed}{inconsistent}":
        "{sections} 个 {section_m:.0f} m 区段中 {consistent} 个与其 1σ 一致{bad}{resets}{detours}{steps}{missed}{inconsistent}",
    "; not valid: {share_pct:.0f} % of the length": "；无效：占长度的 {share_pct:.0f} %",
    "; {count} filter reset(s)": "；滤波器重置 {count} 次",
    "; {count} detour(s) of a source between two resets": "；两次重置之间 {count} 段随观测源偏离又返回",
    "; {count} step(s) of a position source that stayed": "；定位观测源 {count} 处跳变未返回",
    "after the filter reset at t = {time_s:.1f} s the solution follows {source} {off_m:.3f} m from where it was: the "
    "absolute position (the deviations from the design) before or after it is off by about that much, a wrong fix "
    "that stayed or one before it; check against a control point":
        "t = {time_s:.1f} s 滤波器重置后，解随{source}偏离原位置 {off_m:.3f} m：其前或其后的绝对位置（相对设计的偏差）"
        "约有同等误差，可能是保持下来的错误固定解或其前的错误固定解；请用控制点检核",
    "between the filter resets at t = {first_s:.1f} s and {second_s:.1f} s the solution followed {source} {off_m:.3f} m "
    "off and back: the source was wrong there (a false fix), or before and after":
        "在 t = {first_s:.1f} s 与 {second_s:.1f} s 两次滤波器重置之间，解随{source}偏离 {off_m:.3f} m 后又返回："
        "该段观测源有误（假固定解），或其前后有误",
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
    # the design core's and the lever-arm/gauge-volts problems (said in the user's language)
    "the rails are placed from the reference rail's point": '钢轨位置由基准轨上的点推算',
    'the sleeper pulses are placed on the track at the detector': '轨枕脉冲按轨枕探测器的位置落到线路上',
    'files.{role} is given: ': '已给出 files.{role}：',
    'trolley.{key}: missing; insrail process needs it because {given}{why} (3 numbers [m], IMU body frame FRD)': 'trolley.{key}：缺失；insrail process 需要它，因为{given}{why}（3 个数 [m]，IMU 载体坐标系 FRD）',
    "the sensor's slope k [mm/V] (thesis eq. 5.3)": '传感器斜率 k [mm/V]（论文式 5.3）',
    "the sensor's offset b [mm] (thesis eq. 5.3)": '传感器零点 b [mm]（论文式 5.3）',
    'missing: the gauge-volts format needs {what}': '缺失：gauge-volts 格式需要{what}',
    "is 0: a slope of 0 mm/V makes every reading the same gauge; expected the calibration's slope (typically a few mm/V)": '为 0：斜率 0 mm/V 使每个读数都得到同一轨距；应为标定所得斜率（通常为几 mm/V）',
    'missing: with temperature_coefficient_mm_per_c give the temperature [°C] at which k and b were calibrated': '缺失：给出 temperature_coefficient_mm_per_c 时还须给出 k 和 b 标定时的温度 [°C]',
    'missing: calibration_temperature_c is given but no temperature coefficient K_T [mm/°C]': '缺失：已给出 calibration_temperature_c，但没有温度系数 K_T [mm/°C]',
    '{value:g}: expected degrees Celsius, {low:g} .. {high:g}': '{value:g}：应为摄氏度，{low:g} .. {high:g}',
    'option {key}: {why}': '选项 {key}：{why}',
    '{before}; {then}': '{before}；{then}',
    "an event in odometer distance needs the survey's odometer data": '以里程计距离给出的事件需要本次测量的里程计数据',
    'odometer distance {start:g}..{end:g} m lies outside the odometer record ({first:.3f}..{last:.3f} m)': '里程计距离 {start:g}..{end:g} m 超出里程计记录范围（{first:.3f}..{last:.3f} m）',
    "time {start:.3f}..{end:.3f} s lies outside the survey's time on the track ({first:.3f}..{last:.3f} s)": '时间 {start:.3f}..{end:.3f} s 超出本次测量在线路上的时间范围（{first:.3f}..{last:.3f} s）',
    'a line takes no radius and no turn': '直线不取半径，也不取转向',
    'an arc needs radius_start_m (its radius)': '圆曲线需要 radius_start_m（其半径）',
    'an arc has one radius: leave radius_end_m empty or equal to radius_start_m': '圆曲线只有一个半径：radius_end_m 留空或等于 radius_start_m',
    "a clothoid needs radius_start_m and radius_end_m ('inf' at a tangent end)": "缓和曲线需要 radius_start_m 和 radius_end_m（与直线相接端为 'inf'）",
    '{kind}: length must be a positive number of metres, got {length!r}': '{kind}：长度应为正的米数，实为 {length!r}',
    "{kind}: turn must be 'left' or 'right', got {turn!r}": "{kind}：转向应为 'left' 或 'right'，实为 {turn!r}",
    'Arc: radius must be a positive finite number of metres, got {radius!r}': '圆曲线：半径应为正的有限米数，实为 {radius!r}',
    'Clothoid: both radii are infinite; that is a Line': '缓和曲线：两端半径均为无穷大，那是直线',
    'Clothoid: both radii are equal; that is an Arc': '缓和曲线：两端半径相等，那是圆曲线',
    'a horizontal alignment needs at least one element': '平面线形至少需要一个线元',
    'Clothoid: {name} must be a positive number of metres or inf, got {radius!r}': '缓和曲线：{name} 应为正的米数或 inf，实为 {radius!r}',
    '{name} must be a finite number, got {value!r}': '{name} 应为有限数，实为 {value!r}',
    'element {number} is not a Line, Clothoid or Arc: {element}': '第 {number} 个线元不是直线、缓和曲线或圆曲线：{element}',
    'element {number} ({after}) does not continue the curvature of element {previous} ({before}): a clothoid must join its neighbours without a jump in curvature (check the radii and turn directions)': '第 {number} 个线元（{after}）与第 {previous} 个线元（{before}）的曲率不连续：缓和曲线与相邻线元相接处曲率不得突变（请检查半径和转向）',
    'station equation {number} falls at station {station:.4f} m, outside the alignment [{start:.4f}, {end:.4f}] m': '第 {number} 个断链位于里程 {station:.4f} m，超出线形范围 [{start:.4f}, {end:.4f}] m',
    'PVI: curve must be one of {kinds}, got {curve!r}': '变坡点：竖曲线类型应为 {kinds} 之一，实为 {curve!r}',
    'PVI: a {curve} curve needs exactly one of curve_length_m or curve_radius_m': '变坡点：{curve} 竖曲线须且只须给出 curve_length_m 或 curve_radius_m 之一',
    'PVI: the curve length or radius must be a finite number >= 0, got {value!r}': '变坡点：竖曲线长度或半径应为不小于 0 的有限数，实为 {value!r}',
    'a vertical profile needs at least two PVIs': '纵断面至少需要两个变坡点',
    '{stations} stations but {values} cant values': '{stations} 个里程，但有 {values} 个超高值',
    'a cant table needs at least two rows': '超高表至少需要两行',
    'cant row {row} at station {station:.4f} m is not after row {previous} at {before:.4f} m; stations must increase': '超高表第 {row} 行（里程 {station:.4f} m）不在第 {previous} 行（{before:.4f} m）之后；里程须递增',
    'PVI: {name} must be a finite number, got {value!r}': '变坡点：{name} 应为有限数，实为 {value!r}',
    "PVI: a curve length or radius is given but the curve kind is 'none'": "变坡点：给出了竖曲线长度或半径，但竖曲线类型为 'none'",
    'PVI {number} at station {station:.4f} m is not after PVI {previous} at station {before:.4f} m; PVI stations must increase': '第 {number} 个变坡点（里程 {station:.4f} m）不在第 {previous} 个变坡点（里程 {before:.4f} m）之后；变坡点里程须递增',
    'PVI {number} is an end of the profile and cannot carry a vertical curve': '第 {number} 个变坡点是纵断面端点，不能设竖曲线',
    'the vertical curve of PVI {number} begins at station {begin:.4f} m, before the end of the vertical curve of PVI {previous} at {end:.4f} m: curves overlap by {overlap:.4f} m': '第 {number} 个变坡点的竖曲线起于里程 {begin:.4f} m，早于第 {previous} 个变坡点竖曲线的终点 {end:.4f} m：两竖曲线重叠 {overlap:.4f} m',
    'the vertical curve of PVI {number} ends at station {end:.4f} m, beyond PVI {next} at {station:.4f} m': '第 {number} 个变坡点的竖曲线止于里程 {end:.4f} m，超过第 {next} 个变坡点（{station:.4f} m）',
    'cant row {row}: {what} is not a finite number': '超高表第 {row} 行：{what} 不是有限数',
    'the vertical curve of PVI {number} begins at station {begin:.4f} m, before PVI 1 at {end:.4f} m': '第 {number} 个变坡点的竖曲线起于里程 {begin:.4f} m，早于第 1 个变坡点（{end:.4f} m）',
    'PVI {number}: the grades in and out are equal, so a circular curve length cannot define a radius': '第 {number} 个变坡点：前后坡度相等，圆形竖曲线的长度无法确定半径',
    "a design with station equations cannot be reversed: the other direction's chainage (its own station equations) must come from the railway's drawings": '含断链的设计线形不能反向：另一方向的里程（及其自身的断链）须取自铁路设计图',
    "the station prefix {prefix!r} may not hold digits, '+' or '-'": "里程冠号 {prefix!r} 不得含数字、'+' 或 '-'",
    'station equation {number} (back {back:.4f} m) does not come after equation {previous} (ahead {ahead:.4f} m): the displayed station must increase between them': '第 {number} 个断链（断前 {back:.4f} m）不在第 {previous} 个断链（断后 {ahead:.4f} m）之后：两者之间的显示里程须递增',
    'unknown RTKLIB option {key!r}': '未知的 RTKLIB 选项 {key!r}',
    '{key} = {value!r}: expected an integer': '{key} = {value!r}：应为整数',
    '{key} = {value!r}: expected a number': '{key} = {value!r}：应为数值',
    '{key} = {value!r}: expected one of {choices}': '{key} = {value!r}：应为 {choices} 之一',
    'IMU profile not found: {name} (shipped profiles: {shipped})': '未找到 IMU 配置文件：{name}（随软件提供的配置：{shipped}）',
    '{path}: not valid TOML: {error}': '{path}：不是有效的 TOML：{error}',
    '{section}.{key}: expected a non-negative number, found {raw!r}': '{section}.{key}：应为非负数，实为 {raw!r}',
    '{section}.{key}: a correlation time must be positive': '{section}.{key}：相关时间须为正数',
    'range: expected a table [range]': 'range：应为表 [range]',
    'range.{key}: unknown key (expected {expected})': 'range.{key}：未知的键（应为 {expected}）',
    'range.{key}: expected a positive number, found {raw!r}': 'range.{key}：应为正数，实为 {raw!r}',
    'rate_hz: expected a positive number, found {rate!r}': 'rate_hz：应为正数，实为 {rate!r}',
    '{path}: invalid IMU profile:\n  {problems}': '{path}：IMU 配置文件无效：\n  {problems}',
    '{before}\n  {then}': '{before}\n  {then}',
    'StationEquation: {name} must be a finite number, got {value!r}': '断链：{name} 应为有限数，实为 {value!r}',
    'displayed station {station:.4f} m lies in a short chain: it does not exist on this line': '显示里程 {station:.4f} m 位于短链内：本线上不存在该里程',
    'displayed station {station:.4f} m exists twice (long chain): give its zone': '显示里程 {station:.4f} m 出现两次（长链）：请给出其所在区段',
    'zone must be between 0 and {count}': '区段应在 0 到 {count} 之间',
    'a displayed station does not exist in the zone given for it': '所给区段内不存在该显示里程',
    "{text!r} is not a station label like '{prefix}1+234.567'": "{text!r} 不是形如 '{prefix}1+234.567' 的里程标记",
    'station label {text!r} has prefix {found!r}, expected {prefix!r}': '里程标记 {text!r} 的冠号为 {found!r}，应为 {prefix!r}',
    "station label {text!r}: the metres after '+' must be below 1000": "里程标记 {text!r}：'+' 后的米数须小于 1000",
    'section {name}: survey {survey} has no valid sleeper': '区段 {name}：测量 {survey} 没有有效轨枕',
    'section {name}: no sleeper of {surveys} lies between {start} and {end} m': '区段 {name}：{surveys} 没有轨枕位于 {start} 到 {end} m 之间',
    'options_overrides[{key!r}]: {problem}': 'options_overrides[{key!r}]：{problem}',
    'RTKLIB refused {key} = {value!r}': 'RTKLIB 拒绝了 {key} = {value!r}',
    '{key} = {value!r}: insrail does not let RTKLIB write files of its own; leave it empty': '{key} = {value!r}：insrail 不允许 RTKLIB 自行写文件；请留空',
    'insrail needs {needed}: cannot use {forced}': 'insrail 需要 {needed}：不能使用 {forced}',
    'GNSS post-processing failed: {error}': 'GNSS 后处理失败：{error}',
}
